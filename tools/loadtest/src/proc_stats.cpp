#include "ricochet/loadtest/proc_stats.h"

#include <unistd.h>

#include <fstream>
#include <sstream>

namespace ricochet::loadtest {

std::optional<ProcSample> read_proc(int pid, std::string& error) {
  const std::string base = "/proc/" + std::to_string(pid);
  std::ifstream stat(base + "/stat");
  std::string line;
  if (!stat || !std::getline(stat, line)) {
    error = "cannot read " + base + "/stat (is process " + std::to_string(pid) + " running?)";
    return std::nullopt;
  }
  // The command name is in parentheses and may hold spaces: fields count from the last ')'.
  const std::size_t close = line.rfind(')');
  if (close == std::string::npos) {
    error = base + "/stat has no ')' after the command name";
    return std::nullopt;
  }
  std::istringstream fields(line.substr(close + 1));
  std::string field;
  double utime = -1;
  double stime = -1;
  // Field 3 (state) is the first after ')'; utime and stime are fields 14 and 15.
  for (int index = 3; index <= 15 && fields >> field; ++index) {
    if (index == 14) utime = std::strtod(field.c_str(), nullptr);
    if (index == 15) stime = std::strtod(field.c_str(), nullptr);
  }
  if (utime < 0 || stime < 0) {
    error = base + "/stat has fewer than 15 fields";
    return std::nullopt;
  }
  const double ticks_per_s = static_cast<double>(sysconf(_SC_CLK_TCK));
  ProcSample sample;
  sample.cpu_s = (utime + stime) / ticks_per_s;

  std::ifstream status(base + "/status");
  while (std::getline(status, line)) {
    if (line.rfind("VmRSS:", 0) == 0) {
      sample.rss_bytes = std::strtod(line.c_str() + 6, nullptr) * 1024.0;  // "VmRSS:  1234 kB"
      break;
    }
  }
  return sample;
}

double cpu_percent(const ProcSample& from, const ProcSample& to, double wall_s) {
  if (!(wall_s > 0)) return 0;
  return (to.cpu_s - from.cpu_s) / wall_s * 100.0;
}

}  // namespace ricochet::loadtest
