#pragma once
/// A whole file as text: what a child process of an integration test wrote (its log, its JSON).

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace ricochet::test {

/// The file's bytes; empty when it cannot be read.
inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace ricochet::test
