#pragma once
/// What a load test saw, sample by sample (one per scrape), and the summary of each step's
/// measured window: the figures report.json carries and the plots draw.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "ricochet/loadtest/error_kinds.h"
#include "ricochet/loadtest/server_figures.h"
#include "ricochet/loadtest/server_tracker.h"

namespace ricochet::loadtest {

/// One look at every bot and at every server's latest scrape (the servers' figures summed, or
/// their worst where a sum means nothing: tick times, the busiest server's CPU and RSS).
struct RunSample {
  double t_s = 0;     ///< since the run started
  int step_bots = 0;  ///< the step's target bot count
  bool measuring = false;
  int playing = 0;         ///< bots with a connected game channel
  int joining = 0;         ///< bots on their way (connecting, signing in, joining, handshaking)
  int done = 0;            ///< bots that stopped (gave up)
  bool server_ok = false;  ///< every server's latest scrape succeeded
  int matches = 0;
  int server_players = 0;
  TickQuantiles tick;           ///< each quantile's worst match (last 600 ticks)
  double tick_p99_mean_ms = 0;  ///< mean over matches with players of their p99
  double overruns = 0;          ///< since the run started, all matches
  double dropped_steps = 0;     ///< since the run started
  /// The busiest server's, from its /metrics, since its previous scrape (100: one core).
  double server_cpu_percent = 0;
  double server_rss_mb = 0;  ///< the largest server's, from its /metrics
  double generator_cpu_percent = 0;
  double generator_rss_mb = 0;
  double kbps_in_per_client = 0;   ///< bots' received game bytes since the previous sample
  double kbps_out_per_client = 0;  ///< bots' sent game bytes since the previous sample
  double server_packets_in_per_s = 0;
  double server_packets_out_per_s = 0;
  double rtt_ms_p50 = 0;  ///< over the bots' latest RTT samples
  double rtt_ms_p99 = 0;
  double snapshot_loss = 0;  ///< since the previous sample, 0..1
  std::uint64_t errors = 0;  ///< since the run started, every kind
  double scrape_ms = 0;      ///< how long GET /metrics took
};

/// One match's tick quantiles at one sample.
struct MatchTickRow {
  double t_s = 0;
  std::uint32_t server = 0;  ///< index in the run's servers (match ids are per server)
  std::uint32_t match = 0;
  TickQuantiles tick;
};

/// A step's measured window.
struct StepSummary {
  int bots = 0;
  int bots_connected = 0;  ///< playing at the end of the window
  int bots_gave_up = 0;
  int matches = 0;
  double measured_s = 0;
  double ramp_s = 0;                   ///< from the step's first start to the window's start
  TickQuantiles server_tick;           ///< the window's worst of each quantile
  double server_tick_ms_p99_mean = 0;  ///< mean over samples of the mean match p99
  double overruns = 0;                 ///< during the window
  double dropped_steps = 0;
  double snapshot_loss = 0;  ///< bots' lost / (received + lost) during the window
  double snapshots_per_s_per_bot = 0;
  double rtt_ms_p50 = 0;  ///< pooled over the window's samples
  double rtt_ms_p99 = 0;
  double kbps_in_per_client = 0;
  double kbps_out_per_client = 0;
  double kbps_in_total = 0;  ///< every bot's game bytes received over the window, kbit/s
  double kbps_out_total = 0;
  /// The busiest server's over the window, from its /metrics (process_cpu_seconds_total); from
  /// its /proc when /metrics never had it (server_cpu_source).
  double server_cpu_percent = 0;
  double server_rss_mb = 0;  ///< the window's largest of any server, as server_cpu_percent
  const char* server_cpu_source = "none";  ///< "metrics", "proc" or "none"
  /// The same server's CPU and RSS from /proc, for the comparison; -1: /proc not read.
  double server_cpu_percent_proc = -1;
  double server_rss_mb_proc = -1;
  double servers_cpu_percent_total = 0;  ///< every server's CPU summed (200: two cores)
  double servers_rss_mb_total = 0;       ///< every server's largest RSS summed
  std::vector<ServerWindow> servers;     ///< each server over the window
  double generator_cpu_percent = 0;
  double generator_rss_mb = 0;
  double server_packets_in_per_s = 0;
  double server_packets_out_per_s = 0;
  double connect_ms_p50 = 0;  ///< this step's bots: start to first snapshot
  double connect_ms_p99 = 0;
  double connect_ms_max = 0;
  double snapshots_received = 0;  ///< by the bots during the window
  double snapshots_lost = 0;
  /// The samples behind the latency percentiles, kept so that reports of generators run at the
  /// same time merge into exact percentiles of the union (merge.h), not a mean of percentiles:
  /// each playing bot's latest RTT at each scrape of the window, and this step's bots' connect
  /// times, ms.
  std::vector<double> rtt_ms_samples;
  std::vector<double> connect_ms_samples;
  /// Placement (find_match): the step's bots by the server of their latest placement
  /// ("host:control_port" from the assignment; bots never placed are left out).
  std::map<std::string, int> bots_placed;
  /// The step's bots' placements, find_match to the first snapshot, ms (every placement of every
  /// bot, retries and moves included: BotMetrics::placement_ms), and their nearest-rank
  /// percentiles as connect_ms's.
  std::vector<double> placement_ms_samples;
  double placement_ms_p50 = 0;
  double placement_ms_p99 = 0;
  double placement_ms_max = 0;
  ErrorCounts errors;  ///< since the run started, by kind
  /// Server tick time per phase over the window, all matches of every server, in % of one core
  /// ("total": the whole ticks; the rest of server_cpu_percent is the network, the transport and
  /// the control channel).
  std::map<std::string, double> server_phase_percent;

  /// Fills the step's server figures from `servers`: overruns, dropped steps, packets and phase
  /// time summed; server_cpu_percent and server_rss_mb the busiest server's (by /metrics, else by
  /// /proc: server_cpu_source), with its /proc figures; the totals.
  void total_servers();
  /// Whether the step meets every capacity criterion (capacity.h).
  bool meets_capacity() const;
  /// Whether the load generator's own core was the limit (capacity.h).
  bool generator_saturated() const;
  /// One JSON object (no newline); with `samples`, rtt_ms_samples, connect_ms_samples and
  /// placement_ms_samples too.
  std::string to_json(bool samples = false) const;
};

}  // namespace ricochet::loadtest
