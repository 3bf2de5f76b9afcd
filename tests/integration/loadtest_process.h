#pragma once
/// The real ricochet-loadtest binary run to its end (its --duration bounds it), and what it
/// wrote: the end-to-end tests of the load test and of the soak.

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <regex>
#include <sstream>
#include <string>

#include "text_file.h"

namespace ricochet::test {

/// The number after `"key":` at the top level of report.json (its last occurrence: the step
/// objects come first); nullopt when absent.
inline std::optional<double> number_field(const std::string& json, const std::string& key) {
  const std::regex pattern("\"" + key + "\":(-?[0-9.eE+-]+)");
  std::optional<double> last;
  for (std::sregex_iterator it(json.begin(), json.end(), pattern), end; it != end; ++it) {
    last = std::stod((*it)[1].str());
  }
  return last;
}

/// Runs ricochet-loadtest with `arguments`, its output into `log`; its exit code (-1: it did
/// not exit normally).
inline int run_loadtest(const std::string& arguments, const std::filesystem::path& log) {
  const std::string command =
      std::string(RICOCHET_LOADTEST_BINARY) + " " + arguments + " > '" + log.string() + "' 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace ricochet::test
