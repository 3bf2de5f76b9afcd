#pragma once
/// The server's own figures, read from one /metrics scrape: per-match tick quantiles over the
/// match's last 600 ticks, overruns, players, traffic and refusals.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "ricochet/loadtest/prometheus_text.h"

namespace ricochet::loadtest {

/// A match's tick time over its last 600 ticks as /metrics gives it (ricochet_tick_seconds
/// {quantile}: nearest rank, ricochet/stats/percentile.h), ms.
struct TickQuantiles {
  double p50_ms = 0;
  double p95_ms = 0;
  double p99_ms = 0;
  double max_ms = 0;

  /// Each quantile the larger of this one's and other's.
  TickQuantiles worst_with(const TickQuantiles& other) const;
};

struct MatchFigures {
  TickQuantiles tick;
  int connected = 0;    ///< players connected
  double overruns = 0;  ///< ticks that hit the catch-up cap, since the match opened
};

struct ServerFigures {
  int pid = 0;  ///< ricochet_process_id; 0: not reported
  int matches = 0;
  int players = 0;           ///< seated in any match
  int game_connected = 0;    ///< game connections connected
  double overruns = 0;       ///< all matches now listed
  double dropped_steps = 0;  ///< all matches now listed
  double packets_in = 0;     ///< game channel, since start
  double packets_out = 0;
  double bytes_in = 0;
  double bytes_out = 0;
  double game_dropped = 0;     ///< game datagrams dropped, every reason
  double control_refused = 0;  ///< control connections, frames and messages refused
  double open_fds = -1;        ///< process_open_fds; -1: not reported
  double resident_bytes = -1;  ///< process_resident_memory_bytes; -1: not reported
  double cpu_seconds = -1;     ///< process_cpu_seconds_total, user + system; -1: not reported
  /// Process metrics whose value was not a finite number >= 0 (left at -1, not used).
  int bad_values = 0;
  double db_bytes = -1;  ///< ricochet_db_file_bytes (the file and its WAL); -1: not reported
  std::map<std::uint32_t, MatchFigures> by_match;
  /// ricochet_placement_tickets_total by result ("assigned", "no_server_available", ...): the
  /// find_match requests this server answered since it started.
  std::map<std::string, double> placement_tickets;
  /// Tick time spent in each phase (ricochet_tick_phase_seconds_sum), all matches, s since
  /// they opened; "total" is the whole tick.
  std::map<std::string, double> phase_seconds;

  /// The largest of each quantile over the matches with players connected (all zeros: none).
  TickQuantiles worst_tick() const;
};

/// What the samples say; unknown metrics are ignored, a match label that is not a number is
/// skipped.
ServerFigures read_server_figures(const std::vector<MetricSample>& samples);

}  // namespace ricochet::loadtest
