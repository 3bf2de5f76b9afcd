#pragma once
/// What a player feels, measured by a bot: round trip, snapshot rate and loss, bandwidth, time to
/// the first snapshot, kills and deaths it saw, and what it refused from the server. Sans-IO:
/// every time is passed in.

#include <cstdint>
#include <string>
#include <vector>

#include "ricochet/proto/transport_counters.h"

namespace ricochet::bot {

/// Counts the snapshots a connection missed: gaps in ServerPayload.server_tick larger than the
/// snapshot interval (tick_rate / snapshot_rate ticks).
class SnapshotGapCounter {
 public:
  /// ticks_per_snapshot: > 0.
  explicit SnapshotGapCounter(double ticks_per_snapshot) : interval_(ticks_per_snapshot) {}
  /// One snapshot decoded at `tick` (ticks arrive increasing: the decoder refuses stale ones).
  void on_snapshot(std::uint32_t tick);
  std::uint64_t received() const { return received_; }
  std::uint64_t lost() const { return lost_; }

 private:
  double interval_;
  bool has_last_ = false;
  std::uint32_t last_tick_ = 0;
  std::uint64_t received_ = 0;
  std::uint64_t lost_ = 0;
};

struct BotMetrics {
  // Game channel, all connections together.
  std::uint64_t packets_in = 0;
  std::uint64_t packets_out = 0;
  std::uint64_t bytes_in = 0;
  std::uint64_t bytes_out = 0;
  double connected_s = 0;            ///< s the game channel was connected
  std::uint64_t snapshots = 0;       ///< decoded
  std::uint64_t snapshots_lost = 0;  ///< gaps in server_tick (SnapshotGapCounter)
  /// The server's packets by sequence (GameClient::receive_stats): what it sent up to the newest
  /// that came, and of those the ones that never came. Unlike snapshots_lost, a tick the server
  /// sent no snapshot for (a catch-up step) is not counted.
  std::uint64_t server_packets = 0;
  std::uint64_t server_packets_missing = 0;
  std::vector<double> rtt_ms;     ///< the transport's smoothed round trip, one sample per second
  double first_snapshot_ms = -1;  ///< from start() to the first decoded snapshot; -1: none
  double last_reconnect_ms = -1;  ///< from losing the game channel to its next snapshot; -1: none
  /// Placement (find_match): from a placement's first find_match to the first snapshot of the
  /// match it led to, ms, one sample per placement (retries and moves to another server
  /// included).
  std::vector<double> placement_ms;

  // What the bot refused (untrusted input, counted and logged, never trusted).
  std::uint64_t bad_payloads = 0;       ///< unreliable bytes that are not a ServerPayload
  std::uint64_t bad_events = 0;         ///< reliable messages that are not a GameEvent
  std::uint64_t snapshots_refused = 0;  ///< the decoder's refusals (any reason)
  std::uint64_t bad_control = 0;        ///< control frames or replies that make no sense
  std::uint64_t transport_drops = 0;    ///< datagrams the game client dropped (any reason)
  std::uint64_t send_failures = 0;      ///< datagrams the socket could not take (lost)

  // The game as the bot saw it (the running phase only, where the match counts). Kills and
  // deaths include what an arrival's scoreboard showed went with an old connection
  // (score_resyncs).
  int kills = 0;        ///< Kill events naming this bot's entity as killer of another
  int deaths = 0;       ///< Kill events naming this bot's entity as victim
  int kill_events = 0;  ///< every Kill event seen
  int hits_dealt = 0;   ///< Hit events with this bot as attacker
  int reconnects = 0;   ///< game connections after the first
  int resumes = 0;      ///< sign-ins with the session token (Resume) instead of the password
  /// Arrivals whose scoreboard differed from the bot's own count (Kill events that went with
  /// an old connection); the bot took the server's figures.
  int score_resyncs = 0;
  int matches = 0;  ///< MatchResults received
  std::uint64_t inputs_sent = 0;
  std::uint64_t weapon_switches = 0;

  // Prediction (predictor.h): empty in cheap mode and without a usable collision world.
  std::vector<double> prediction_error_m;  ///< one sample per newly acknowledged input, m
  std::uint64_t prediction_resets = 0;     ///< re-seeds from the server (spawns, deaths, jumps)
  std::uint64_t prediction_replayed = 0;   ///< inputs replayed on corrections
  double own_travelled_m = 0;  ///< how far the server moved the bot's player (while predicting)
  std::uint64_t worlds_refused = 0;  ///< join replies whose collision world was unusable

  // The network simulator (link_simulator.h), both directions.
  std::uint64_t sim_dropped = 0;
  std::uint64_t sim_duplicated = 0;
  std::uint64_t sim_reordered = 0;

  /// Adds one finished game connection's transport counters.
  void add_transport(const proto::TransportCounters& counters, double connected_for_s);
  /// Sums another bot's metrics into this one (samples are appended; first_snapshot_ms and
  /// last_reconnect_ms keep the largest, the worst bot's).
  void merge(const BotMetrics& other);
  /// One JSON object (no newline): the counts and the rates per second of connection.
  std::string to_json() const;
};

}  // namespace ricochet::bot
