#pragma once
/// One match on the network: the socket-free Match on its own strand, ticked by a timer at the
/// times the match asks for (rounded up to the 1 ms grid every match shares: tick_wake.h), its
/// outbox drained into the game channel after every tick. Every call posts to the strand, so the
/// Match is touched by one thread at a time and never waits for another match, the socket or the
/// database.
///
///   timer ─▶ Match::tick(now) ─▶ outbox ─▶ GameChannel::send ─▶ socket
///   GameRouter (registry) ─post─▶ connect / disconnect / receive / chat / leave
///
/// A match ends by itself (frag or time limit, after a tick: MatchEnded handler) or by end()
/// (the server stops: aborted). Either way the host stops ticking and hands over one EndedMatch.

#include <atomic>
#include <boost/asio/awaitable.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

#include "game_channel.h"
#include "ricochet/db/records.h"
#include "ricochet/server/live_frame.h"
#include "ricochet/server/match.h"
#include "ricochet/server/metrics.h"
#include "tick_window.h"

namespace ricochet::server {

class RecordingFiles;

/// What a scrape or the directory reads about a match, refreshed after every tick.
struct MatchHostStats {
  MatchCounters counters;
  TickProfile last_profile;
  int seated = 0;  ///< connected plus within the reconnect grace
  int connected = 0;
  proto::TimeUs last_tick_at = 0;  ///< steady µs of the last tick() call (or of the opening)
  MatchPhase phase = MatchPhase::Waiting;
  std::uint32_t tick = 0;             ///< the match's tick number
  std::uint32_t phase_ends_tick = 0;  ///< 0: the phase has no end
  /// Who leads (a player's name in ffa, "red" or "blue" in tdm; empty: no score above 0, or the
  /// teams tied) and with what score; looked up once a second of ticks, not every tick.
  std::string leader;
  int leader_score = 0;
};

/// A match that ended: its record for the DB, who played (for their MatchResults) and its
/// recording.
///
/// Who is in the record, and their seconds_played, are the match's own count on its ticks
/// (match_record.h): the players who took part while it was running, for their running time
/// connected.
struct EndedMatch {
  std::uint32_t id = 0;
  db::MatchRecord record;              ///< players empty when nobody played; aborted when stopped
  std::vector<std::string> usernames;  ///< one per record.players entry
  /// Every account still seated when it ended, in the record or not (one who only waited for
  /// opponents is not): each gets the match's MatchResults.
  std::vector<std::uint64_t> seated;
  wire::MatchEndReason end_reason = wire::MATCH_END_REASON_SERVER_SHUTDOWN;
  /// The finished recording, less what was streamed to RecordingFiles::part_name(id,
  /// record.started_ms) while it ran; empty when recording is off or nobody ever joined.
  std::vector<std::uint8_t> recording;
};

/// Called once, on the match's strand, when the match ended by itself (frag or time limit),
/// after the MatchEnded event went into the game channel.
using MatchEndedHandler = std::function<void(EndedMatch)>;

/// Reported to the owner when a player is no longer in the match (refused, or its reconnect
/// grace ran out), so that its seat can be given to someone else. `seat` is the generation the
/// player connected with (MatchRegistry), so a seat taken again since is not released.
using SeatReleased =
    std::function<void(std::uint64_t account, std::uint32_t match_id, std::uint64_t seat)>;

class MatchHost : public std::enable_shared_from_this<MatchHost> {
 public:
  /// `recordings`: where the recording streams once a player joined (null: it is all handed
  /// over at the end).
  MatchHost(boost::asio::io_context& io, Match match, GameChannel& channel, SeatReleased released,
            MatchEndedHandler ended, RecordingFiles* recordings = nullptr);
  ~MatchHost();
  MatchHost(const MatchHost&) = delete;
  MatchHost& operator=(const MatchHost&) = delete;

  /// Starts ticking.
  void start();
  /// Stops ticking, tells the players the match ended (MatchEnded, server shutdown) and hands
  /// over the match, aborted, on the match's strand. A match that had already ended by itself
  /// hands over an empty one (its id only: it was handed to the MatchEndedHandler).
  void end(std::function<void(EndedMatch)> done);

  // Thread-safe; each posts to the match's strand.
  /// `seat`: the registry's generation of the account's seat, handed back in SeatReleased.
  void connect(std::uint64_t account, std::string name, std::uint64_t seat);
  void disconnect(std::uint64_t account);
  /// Payloads of seated players, in order, in one post. Half of each one's round trip
  /// (GamePayload::rtt_us; 0: not measured yet) is the latency lag compensation rewinds by.
  void receive(std::vector<GamePayload> payloads);
  void chat(std::uint64_t account, std::string text);
  /// The account left (its seat is already released and its connection kicked).
  void leave(std::uint64_t account);

  std::uint32_t id() const { return id_; }
  const std::string& name() const { return name_; }
  const std::string& map_name() const { return map_name_; }
  GameMode mode() const { return mode_; }
  int max_players() const { return max_players_; }
  int tick_rate_hz() const { return tick_rate_hz_; }
  int snapshot_rate_hz() const { return snapshot_rate_hz_; }
  const proto::QuantizationSpec& quantization() const { return quantization_; }
  MatchHostStats stats() const;
  /// The match's live feed (live_frame.h), made on the first call with `config` (valid) and
  /// handed to the match on its strand; the same feed after. Thread-safe.
  std::shared_ptr<LiveFeed> live_feed(const LiveFeedConfig& config);
  /// The tick times of the last kTickWindowTicks ticks, s (the quantiles /metrics reports).
  stats::Summary tick_summary() const;
  /// Reports the per-phase tick histograms (ricochet_tick_phase_seconds{match, phase}; they
  /// go with the host) and the quantiles of the last ticks (ricochet_tick_seconds{match,
  /// quantile}).
  void report_phases(MetricsSink& sink) const;

 private:
  struct Played {
    bool seated = true;      ///< false once the seat was released
    std::uint64_t seat = 0;  ///< the seat generation it connected with
  };

  boost::asio::awaitable<void> tick_loop(std::shared_ptr<MatchHost> self);
  void tick(proto::TimeUs now);
  /// The match as it ended, with the recording.
  EndedMatch ended_match(bool aborted);
  void drain_outbox();
  /// Hands the recording's completed chunks to the file in progress, once someone played and
  /// while the disk keeps up (else they wait in the match's writer, within its max bytes).
  void stream_recording();
  void observe_profile(const TickProfile& profile);
  /// Seats whose player the match no longer has (grace ran out) are released.
  void sweep_departed();
  void publish_stats(proto::TimeUs now);
  /// Sets stats_.leader and leader_score from the scoreboard; the caller holds stats_mutex_.
  void find_leader();

  Match match_;
  GameChannel& channel_;
  SeatReleased released_;
  MatchEndedHandler on_ended_;
  RecordingFiles* recordings_;
  boost::asio::strand<boost::asio::io_context::executor_type> strand_;
  boost::asio::steady_timer timer_;
  const std::uint32_t id_;
  const std::string name_;
  const std::string map_name_;
  const GameMode mode_;
  const int max_players_;
  const int tick_rate_hz_;
  const int snapshot_rate_hz_;
  const proto::QuantizationSpec quantization_;
  db::UnixMillis started_unix_ms_ = 0;
  std::string recording_part_;  ///< the file in progress: RecordingFiles::part_name()
  bool ended_ = false;
  std::unordered_map<std::uint64_t, Played> played_;  ///< everyone who connected, by account
  proto::TimeUs next_sweep_at_ = 0;
  std::uint32_t next_leader_tick_ = 0;  ///< the tick from which the leader is looked for again
  std::vector<std::unique_ptr<Histogram>> phase_histograms_;  ///< by kPhaseNames
  mutable std::mutex stats_mutex_;
  MatchHostStats stats_;
  TickWindow tick_window_;  ///< the tick's total time; guarded by stats_mutex_
  std::mutex live_mutex_;
  std::shared_ptr<LiveFeed> live_feed_;  ///< made by live_feed(); guarded by live_mutex_
};

}  // namespace ricochet::server
