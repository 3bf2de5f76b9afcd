#pragma once
/// The dashboard's overview (issue 32): what the server measures anyway (MatchHost::stats(), its
/// tick window, the channels' counters, the DB queue), sampled about once a second off the match
/// strands, as the JSON the page reads: each match with its tick p50/p99 over the last samples
/// (the sparklines), the server's players, bandwidth and queue depth, and every drop and refusal
/// with a count above 0, by channel and reason. Socket-free and time passed in; the server takes
/// the samples and sends the JSON (GET /api/overview and its event stream).
///
/// The JSON is one object of sections, so another (the fleet's servers) joins as a key:
///   {"at_s": s since the first sample, "server": {..., "fleet": bool}, "matches": [...],
///    "refusals": [{"channel", "reason", "count", "expected": true only when set}]}
/// "fleet": the server keeps a row in the fleet directory, so GET /fleet answers (fleet_view.h);
/// the page reads that itself, only while it is open: a directory read per viewer, not per sample.

#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ricochet/proto/clock.h"

namespace ricochet::server {

/// One match as sampled.
struct OverviewMatch {
  std::uint32_t id = 0;
  std::string name;
  std::string map;
  std::string mode;   ///< "ffa", "tdm"
  std::string phase;  ///< "waiting", "warmup", "running", "ended"
  int seated = 0;
  int connected = 0;
  int max_players = 0;
  std::string leader;  ///< empty: nobody leads
  int leader_score = 0;
  std::optional<double> time_left_s;  ///< of the phase; nullopt: it has no end
  double tick_p50_ms = 0;             ///< over the match's tick window
  double tick_p99_ms = 0;
  std::uint64_t overruns = 0;  ///< ticks that hit the catch-up cap, since the match began
};

/// A count of refused or dropped things, since the start.
struct OverviewRefusal {
  std::string channel;  ///< "game", "control", "match", "admin" ...
  std::string reason;
  std::uint64_t count = 0;
  /// Part of normal operation, not a problem: an input already applied arriving again in a
  /// later packet (each packet repeats the last inputs, PROTOCOL.md). Shown apart.
  bool expected = false;
};

/// The whole server at one moment.
struct OverviewSample {
  std::vector<OverviewMatch> matches;
  std::size_t players = 0;     ///< seated in any match
  std::uint64_t bytes_in = 0;  ///< game and control channels, since the start
  std::uint64_t bytes_out = 0;
  std::size_t db_queue_depth = 0;  ///< jobs waiting for the DB thread
  bool fleet = false;              ///< in the fleet directory: GET /fleet answers
  std::vector<OverviewRefusal> refusals;
};

class Overview {
 public:
  /// history: samples of tick times kept per match, > 0 (120: two minutes at 1 Hz).
  explicit Overview(std::size_t history = 120);

  /// Takes the sample made at `now` (steady µs, later than the last) and returns the JSON.
  /// Bandwidth is the bytes since the last sample over the time since it (0 at the first).
  std::string update(proto::TimeUs now, const OverviewSample& sample);

 private:
  struct TickHistory {
    std::deque<double> p50_ms;
    std::deque<double> p99_ms;
  };

  std::size_t history_;
  std::map<std::uint32_t, TickHistory> ticks_;  ///< by match id; ended matches forgotten
  std::optional<proto::TimeUs> first_at_;
  proto::TimeUs last_at_ = 0;
  std::uint64_t last_in_ = 0;
  std::uint64_t last_out_ = 0;
};

}  // namespace ricochet::server
