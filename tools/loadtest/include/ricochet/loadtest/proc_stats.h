#pragma once
/// A process's CPU time and resident memory from /proc (Linux), for the server under test and
/// for the load generator itself.

#include <optional>
#include <string>

namespace ricochet::loadtest {

struct ProcSample {
  double cpu_s = 0;      ///< user + system CPU time since the process started, s
  double rss_bytes = 0;  ///< resident set size
};

/// /proc/<pid>/stat and /proc/<pid>/status; nullopt (with `error` set) when the process is gone
/// or the files do not read as expected.
std::optional<ProcSample> read_proc(int pid, std::string& error);

/// Busy share of one core between two samples `wall_s` apart, in % (100: one core saturated).
double cpu_percent(const ProcSample& from, const ProcSample& to, double wall_s);

}  // namespace ricochet::loadtest
