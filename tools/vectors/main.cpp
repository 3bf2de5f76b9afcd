/// ricochet-vectors: writes the cross-language test vectors (tests/vectors/README.md).
///   ricochet-vectors --out DIR      write every set into DIR/NAME.txt
///   ricochet-vectors --check DIR    compare every set with DIR/NAME.txt; exit 1 on a difference
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "vector_file.h"

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  CLI::App app{"Writes or checks the cross-language test vectors of tests/vectors/"};
  std::string out, check, only;
  auto* out_option = app.add_option("--out", out, "write every set into this directory");
  app.add_option("--check", check, "compare every set with the files in this directory")
      ->excludes(out_option);
  app.add_option("--only", only, "one set by name");
  CLI11_PARSE(app, argc, argv);
  if (out.empty() && check.empty()) {
    std::fprintf(stderr, "ricochet-vectors: give --out DIR or --check DIR\n");
    return 2;
  }
  int differences = 0, sets = 0;
  for (const ricochet::vectors::VectorSet& set : ricochet::vectors::vector_sets()) {
    if (!only.empty() && only != set.name) continue;
    ++sets;
    const std::string text = set.write();
    if (!out.empty()) {
      fs::create_directories(out);
      std::ofstream file(fs::path(out) / (std::string(set.name) + ".txt"), std::ios::binary);
      file << text;
      if (!file.flush()) {
        std::fprintf(stderr, "ricochet-vectors: cannot write %s into %s\n", set.name, out.c_str());
        return 1;
      }
      std::printf("ricochet-vectors: wrote %s (%zu bytes)\n", set.name, text.size());
      continue;
    }
    const fs::path path = fs::path(check) / (std::string(set.name) + ".txt");
    std::ifstream file(path, std::ios::binary);
    std::ostringstream committed;
    committed << file.rdbuf();
    if (!file || committed.str() != text) {
      ++differences;
      std::fprintf(stderr,
                   "ricochet-vectors: %s differs from what the C++ code writes now; if the change "
                   "is meant, rewrite it with `ricochet-vectors --out tests/vectors` and make the "
                   "Java client follow\n",
                   path.c_str());
    } else {
      std::printf("ricochet-vectors: %s matches\n", path.c_str());
    }
  }
  if (sets == 0) {
    std::fprintf(stderr, "ricochet-vectors: no set named '%s'\n", only.c_str());
    return 2;
  }
  return differences == 0 ? 0 : 1;
}
