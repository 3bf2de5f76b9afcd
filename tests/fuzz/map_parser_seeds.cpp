// Writes the seed corpus of map_parser_fuzz: the sample arena and small maps that use every
// statement, each checked to parse. Run by `tools/fuzz.sh --seeds` from the repo root; the
// output is committed in tests/fuzz/corpus/map_parser/.
//
//   map_parser_seeds DIR

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <variant>

#include "ricochet/server/map.h"

namespace {

const char* const kSmallMaps[][2] = {
    {"minimal", "ricochet-map 1\nname m\nbounds -1 -1 -1 1 1 1\nspawn 0 0 0 0\n"},
    {"every_statement",
     "# every statement once\n"
     "ricochet-map 1\n"
     "name every-statement_1\n"
     "bounds -10 -2 -10 10 8 10\n"
     "floor 0\n"
     "box 1 1 1  0.5 1 0.5  45\n"
     "box -3 0.5 2  1 0.5 1\n"
     "wall -5 -5 5 -5  0 3 0.5\n"
     "mesh ramp\n"
     "  vertex 0 0 0\n  vertex 0 0 2\n  vertex 4 1.5 2\n  vertex 4 1.5 0\n"
     "  triangle 0 1 2\n  triangle 0 2 3\n"
     "end\n"
     "spawn 0 0.45 0 90\n"
     "spawn 2 0.45 -2 -90.5\n"},
    {"two_meshes_crlf",
     "ricochet-map 1\r\nname crlf\r\nbounds -5 -5 -5 5 5 5\r\n"
     "mesh a\r\nvertex 0 0 0\r\nvertex 1 0 0\r\nvertex 0 0 1\r\ntriangle 0 1 2\r\nend\r\n"
     "mesh b\r\nvertex 0 1 0\r\nvertex 1 1e0 0\r\nvertex 0 1 -1.5e-1\r\ntriangle 2 1 0\r\nend\r\n"
     "spawn\t1\t2\t3\t-360\r\n"},
    {"bad_triangle",
     "ricochet-map 1\nname t\nbounds -1 -1 -1 1 1 1\nmesh x\nvertex 0 0 0\n"
     "triangle 0 0 0\nend\nspawn 0 0 0 0\n"},
};

void write(const std::string& path, const std::string& text) {
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (!file || std::fwrite(text.data(), 1, text.size(), file) != text.size() ||
      std::fclose(file) != 0) {
    std::fprintf(stderr, "map_parser_seeds: cannot write %s\n", path.c_str());
    std::exit(1);
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: map_parser_seeds DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  std::ifstream arena("server/maps/arena.map", std::ios::binary);
  if (!arena) {
    std::fprintf(stderr, "map_parser_seeds: run from the repo root (server/maps/arena.map)\n");
    return 1;
  }
  std::stringstream text;
  text << arena.rdbuf();
  write(dir + "/arena.map", text.str());
  for (const auto& [name, map] : kSmallMaps) {
    const bool parses =
        std::holds_alternative<ricochet::server::Map>(ricochet::server::parse_map(map));
    // Every seed but the one with a bad triangle is a valid map.
    if (parses != (std::string(name) != "bad_triangle")) {
      std::fprintf(stderr, "map_parser_seeds: seed %s parses=%d, not as intended\n", name, parses);
      return 1;
    }
    write(dir + "/" + name + ".map", map);
  }
  std::printf("map_parser_seeds: wrote %zu seeds\n", std::size(kSmallMaps) + 1);
  return 0;
}
