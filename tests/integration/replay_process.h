#pragma once
/// `ricochet-replay --json FILE` (and `--export`) run as the operator runs it, for the end-to-end
/// tests that check a server's recordings. Needs RICOCHET_REPLAY_BINARY (the tests' CMakeLists.txt
/// defines it).

#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <utility>

namespace ricochet::test {

/// Its exit code (-1 when it did not exit) and everything it printed.
inline std::pair<int, std::string> replay(const std::filesystem::path& file) {
  const std::string command =
      std::string(RICOCHET_REPLAY_BINARY) + " --json '" + file.string() + "' 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return {-1, "popen failed"};
  std::string output;
  char chunk[4096];
  while (const std::size_t size = std::fread(chunk, 1, sizeof chunk, pipe))
    output.append(chunk, size);
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

/// `ricochet-replay --export CSV FILE`: its exit code (-1 when it did not exit).
inline int replay_export(const std::filesystem::path& file, const std::filesystem::path& csv) {
  const std::string command = std::string(RICOCHET_REPLAY_BINARY) + " --export '" + csv.string() +
                              "' '" + file.string() + "' > /dev/null 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace ricochet::test
