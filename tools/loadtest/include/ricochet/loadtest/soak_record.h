#pragma once
/// What a soak saw, sample by sample (one per scrape), and its summary: the figures report.json
/// carries, the flatness verdict included. summarise_soak is a pure function of the samples.

#include <cstdint>
#include <optional>
#include <vector>

#include "ricochet/loadtest/error_kinds.h"
#include "ricochet/loadtest/flatness.h"

namespace ricochet::loadtest {

/// One scrape of the server and one look at every bot of a soak.
struct SoakSample {
  double t_s = 0;          ///< since the run started
  bool server_ok = false;  ///< the /metrics scrape succeeded
  int playing = 0;         ///< bots with a connected game channel
  int joining = 0;         ///< bots on their way (connecting, signing in, joining, reconnecting)
  int gave_up = 0;         ///< bots that stopped on their own (their slot waits for its turn)
  int server_matches = 0;  ///< matches the server lists
  int server_players = 0;
  double tick_p99_ms = 0;  ///< the worst match's, over its last 600 ticks (matches with players)
  double tick_max_ms = 0;  ///< likewise
  double rss_mib = -1;     ///< the server's resident memory from /proc; -1: not read
  double open_fds = -1;    ///< process_open_fds; -1: not scraped
  double db_mib = -1;      ///< ricochet_db_file_bytes; -1: not scraped
  /// Snapshots the bots could not use since the previous sample, 0..1: lost on the link, or
  /// come after a newer one (stale: the decoder refuses them). With a jitter of ± 50 ms at 60
  /// snapshots a second, stale ones outnumber the lost.
  double snapshot_loss = 0;
  double snapshots = 0;       ///< decoded by every bot so far, since the run started
  double snapshots_lost = 0;  ///< likewise, gaps in the server's ticks (lost or stale)
  /// The server's game packets by sequence, every bot so far: up to the newest that came, and
  /// of those the ones that never came (the link's loss alone; late ones are not missing).
  double server_packets = 0;
  double server_packets_missing = 0;
  double server_cpu_percent = 0;  ///< since the previous sample (100: one core)
  double generator_cpu_percent = 0;
  // Since the run started:
  std::uint64_t sign_ins = 0;          ///< bots that got a session (password logins)
  std::uint64_t new_accounts = 0;      ///< bots that started on an account new to this run
  std::uint64_t departures = 0;        ///< bots that left at the end of their lifetime
  std::uint64_t matches_finished = 0;  ///< distinct matches whose results a bot received
  std::uint64_t errors = 0;            ///< failed attempts and scrapes, every kind
};

/// A soak's figures over its samples; "after the warm-up" means samples at or after warmup_s.
struct SoakSummary {
  double duration_s = 0;  ///< the last sample's time
  int samples = 0;
  Flatness flatness;  ///< RSS and open fds after the warm-up, with the bounds and the verdict
  // The server, after the warm-up (-1: never read):
  double rss_mib_first = -1;
  double rss_mib_last = -1;
  double rss_mib_max = -1;
  double fds_first = -1;
  double fds_last = -1;
  double fds_max = -1;
  // The database over the whole run (-1: never read):
  double db_mib_first = -1;
  double db_mib_last = -1;
  std::optional<double> db_mib_per_hour;  ///< least-squares slope, the whole run
  // Tick time of the worst match, over the samples after the warm-up with a match playing:
  double tick_p99_ms_median = 0;
  double tick_p99_ms_max = 0;
  double tick_max_ms_max = 0;
  /// Bots' lost / (received + lost) snapshots after the warm-up (lost or stale).
  double snapshot_loss = 0;
  /// The server's game packets the bots never got, after the warm-up (the link's loss).
  double packet_loss = 0;
  int playing_min = 0;  ///< bots playing, after the warm-up
  int playing_median = 0;
  std::uint64_t sign_ins = 0;  ///< the last sample's counts (the whole run)
  std::uint64_t new_accounts = 0;
  std::uint64_t departures = 0;
  std::uint64_t matches_finished = 0;
  std::uint64_t errors = 0;
  int scrapes_failed = 0;  ///< samples without the server's /metrics
};

/// The summary of `samples` (in time order) with the slopes fitted after `warmup_s`.
SoakSummary summarise_soak(const std::vector<SoakSample>& samples, double warmup_s,
                           const FlatnessBounds& bounds);

}  // namespace ricochet::loadtest
