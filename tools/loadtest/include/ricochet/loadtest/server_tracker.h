#pragma once
/// One server under load, scrape by scrape: its CPU and RSS from its own /metrics
/// (process_cpu_seconds_total, process_resident_memory_bytes), and from /proc besides when the
/// server is on this host and the load test may read it (ServerProc). Sans-IO: the caller scrapes
/// and reads /proc, the tracker keeps the points and sums up a window. What /metrics says is
/// untrusted: a missing or bad value, or a CPU counter that goes back (a restart), is counted and
/// leaves that interval out, never fatal.

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ricochet/loadtest/loadtest_config.h"
#include "ricochet/loadtest/proc_stats.h"
#include "ricochet/loadtest/server_figures.h"

namespace ricochet::loadtest {

/// One scrape of one server.
struct ServerPoint {
  double t_s = 0;   ///< since the run started
  bool ok = false;  ///< the scrape answered usable exposition text
  int matches = 0;
  int players = 0;              ///< seated in any match
  TickQuantiles tick;           ///< each quantile's worst match with players
  double tick_p99_mean_ms = 0;  ///< mean over matches with players of their p99
  double overruns = -1;         ///< all matches, since they opened; -1: not scraped
  double dropped_steps = -1;
  double packets_in = -1;  ///< game channel, since the server started; -1: not scraped
  double packets_out = -1;
  std::map<std::string, double> phase_seconds;  ///< empty: not scraped
  /// ricochet_placement_tickets_total by result, since the server started; empty: none listed.
  std::map<std::string, double> placement_tickets;
  double cpu_s = -1;             ///< process_cpu_seconds_total; -1: missing or bad
  double rss_mb = -1;            ///< process_resident_memory_bytes / 1e6; -1: missing or bad
  double cpu_s_proc = -1;        ///< from /proc; -1: not read
  double rss_mb_proc = -1;       ///< from /proc; -1: not read
  double cpu_percent = -1;       ///< since the previous point, from /metrics; -1: unknown
  double cpu_percent_proc = -1;  ///< since the previous point, from /proc; -1: unknown
};

/// One server over a step's measured window. CPU is the busy share of one core (100: one core),
/// from the intervals whose both ends have the counter (an interval with a missing value or a
/// counter reset is left out of both the CPU time and the wall time).
struct ServerWindow {
  std::string label;     ///< "host:control_port"
  bool scraped = false;  ///< at least one usable scrape in the window
  int matches = 0;       ///< at the window's last usable scrape
  int players = 0;
  TickQuantiles tick;           ///< the window's worst of each quantile
  double tick_p99_mean_ms = 0;  ///< mean over the window's scrapes of the mean match p99
  double overruns = 0;          ///< during the window
  double dropped_steps = 0;
  double cpu_percent = -1;       ///< from /metrics; -1: no interval had it
  double rss_mb = -1;            ///< the window's largest, from /metrics; -1: never reported
  double cpu_percent_proc = -1;  ///< from /proc; -1: not read
  double rss_mb_proc = -1;
  double packets_in_per_s = 0;
  double packets_out_per_s = 0;
  /// Tick time per phase over the window, % of one core ("total": whole ticks).
  std::map<std::string, double> phase_percent;
  /// find_match requests the server answered over the step (from its start, not only the
  /// window: bots are placed while they ramp), by result (ServerTracker::placement_tickets).
  std::map<std::string, double> placement_tickets;

  /// One JSON object (no newline).
  std::string to_json() const;
};

class ServerTracker {
 public:
  using Count = std::function<void(const std::string& kind)>;

  /// `loopback`: the server's address is on this host. `pid`: from the command line, 0 to take
  /// ricochet_process_id from /metrics. `count` counts a problem by kind into the run's errors.
  ServerTracker(std::string label, ServerProc proc, bool loopback, int pid, Count count);

  /// The pid whose /proc entry the caller should read before observe(), or 0 for none.
  int proc_pid() const;
  /// Records one scrape at `t_s` (`figures` empty: the scrape failed, already counted) and the
  /// /proc read the caller made for proc_pid() (empty: not read or unreadable).
  const ServerPoint& observe(double t_s, const std::optional<ServerFigures>& figures,
                             const std::optional<ProcSample>& proc);

  const std::string& label() const { return label_; }
  const std::vector<ServerPoint>& points() const { return points_; }
  /// The latest point; a default one before the first.
  const ServerPoint& latest() const;
  /// The window [from_t_s, to_t_s]: its deltas start at the last point before from_t_s.
  ServerWindow window(double from_t_s, double to_t_s) const;
  /// ricochet_placement_tickets_total by result between the last usable point at or before
  /// `from_t_s` (the first usable one when none is) and the last usable one at or before
  /// `to_t_s`; a result whose counter went back (a restarted server) is left out, one listed
  /// only at the end counts from 0.
  std::map<std::string, double> placement_tickets(double from_t_s, double to_t_s) const;

 private:
  std::string label_;
  ServerProc proc_;
  bool loopback_;
  int pid_;
  bool proc_given_up_ = false;
  Count count_;
  std::vector<ServerPoint> points_;
};

}  // namespace ricochet::loadtest
