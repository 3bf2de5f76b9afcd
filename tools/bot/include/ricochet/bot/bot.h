#pragma once
/// One bot: a small object pumped by an io_context with timers and callbacks, never a blocking
/// call, so many share one loop. Its life is an explicit state machine; every transition is
/// logged once with its reason:
///
///   Connecting ─TLS up, server trusted─▶ SigningIn ─logged in─▶ Joining ─join reply─▶ Handshaking
///   Handshaking ─connected─▶ Playing ─game channel lost, rebind─▶ Reconnecting ─join reply─▶
///   Handshaking Playing ─match ended─▶ Joining (after its MatchResults: the next match of the
///   rotation) Reconnecting ─control channel lost─▶ Connecting (after a back-off) any ─stop(), a
///   fatal refusal, too many failed reconnects, matches done─▶ Done
///
/// With find_match set (placement, PROTOCOL.md), Joining asks the first server (config host)
/// for an Assignment and follows it: on that server, a join with the ticket; on another,
/// Joining ─assignment─▶ Connecting (there, its certificate pinned from the assignment) ─▶
/// SigningIn (resume with the session token) ─▶ Joining (the ticket) ─▶ Handshaking. Once the
/// match is over (or the ticket refused) the bot goes back to the first server to ask again.
///
/// Each waiting state has a deadline (a state timer); missing it is a failed attempt.

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ip/udp.hpp>
#include <boost/asio/ssl/context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "ricochet/bot/assignment.h"
#include "ricochet/bot/bot_config.h"
#include "ricochet/bot/bot_metrics.h"
#include "ricochet/bot/brain.h"
#include "ricochet/bot/control_client.h"
#include "ricochet/bot/game_feed.h"
#include "ricochet/bot/game_session.h"
#include "ricochet/bot/rendered_view.h"
#include "ricochet/bot/state_dump.h"
#include "ricochet/wire/control.pb.h"
#include "ricochet/wire/game.pb.h"

namespace ricochet::bot {

enum class BotState : std::uint8_t {
  Connecting,
  SigningIn,
  Joining,
  Handshaking,
  Playing,
  Reconnecting,
  Done,
};
const char* name(BotState state);

/// What a bot saw of the match, for its owner (tests check it against the server's results).
struct BotRecord {
  std::uint64_t account_id = 0;
  std::vector<std::uint32_t> entity_ids;   ///< own entity of each game connection, in order
  std::vector<std::uint16_t> local_ports;  ///< local UDP port of each game connection, in order
  /// The Kill events of the current (or last) match's running phase, as received.
  std::vector<wire::Kill> kills;
  /// Per game connection: the first MatchState after arrival (the server's scores) and what
  /// the bot had counted from this match's Kill events until then (on top of the scores it took
  /// at the arrival before, see BotMetrics::score_resyncs).
  struct Arrival {
    std::uint32_t entity_id = 0;  ///< the bot's entity on that connection (0: no payload yet)
    wire::MatchState state;       ///< the first MatchState of the connection
    int kills_counted = 0;
    int deaths_counted = 0;
    int score_counted = 0;
  };
  std::vector<Arrival> arrivals;
  std::vector<wire::MatchResults> results;
  std::vector<wire::MatchEndReason> match_ended;  ///< MatchEnded events, in order
  /// A seat taken with a ticket (find_match): the control channel it was taken on.
  struct Placement {
    std::string server;  ///< "host:port" of that server's control channel
    std::uint32_t match_id = 0;
  };
  std::vector<Placement> placements;  ///< in order
  std::string error;                  ///< why the bot is Done, when it is not a normal end
};

class Bot {
 public:
  /// `tls` and `trust` are shared by the bots of a process and must outlive this bot.
  Bot(boost::asio::io_context& io, boost::asio::ssl::context& tls, ServerTrust& trust,
      BotConfig config);
  ~Bot();
  Bot(const Bot&) = delete;
  Bot& operator=(const Bot&) = delete;

  /// Puts every later game connection on `port` (a socket shared by the bots of a process),
  /// unless the bot moves its address on purpose (rebind_after_s). Before start().
  void share_game_port(std::shared_ptr<SharedGamePort> port) { shared_port_ = std::move(port); }
  void start();
  /// Ends everything (disconnect packets on the game channel) and moves to Done.
  void stop(std::string_view reason);

  BotState state() const { return state_; }
  const BotConfig& config() const { return config_; }
  /// Metrics so far (the current connection's transport counters included).
  BotMetrics metrics() const;
  const BotRecord& record() const { return record_; }
  /// Called once when the bot reaches Done.
  void on_done(std::function<void()> callback) { on_done_ = std::move(callback); }
  /// Called with the reason of every failed attempt, of every refusal the bot answers by itself
  /// (no room in a match, a placement refused: it waits or finds again), and of an end in error
  /// (load tests count them by kind).
  void on_failure(std::function<void(std::string_view reason)> callback) {
    on_failure_ = std::move(callback);
  }

 private:
  void transition(BotState to, std::string_view reason);
  /// Runs `on_expiry` after `seconds` unless re-armed or cancelled first.
  void arm(double seconds, std::function<void()> on_expiry);
  /// How a failed attempt is retried: on the same control connection (it is idle: the reply
  /// came, or none was pending), or on a new one (a reply may still be on its way, or the
  /// connection is gone).
  enum class Retry : std::uint8_t { SameConnection, NewConnection };
  void fail_attempt(const std::string& reason, Retry retry);
  /// The sign-in was refused SERVER_BUSY: signs in again after busy_backoff_s(), which is not
  /// a failed attempt (refusal_policy.h).
  void retry_busy(const std::string& reason);
  void reconnect(const std::string& reason);
  void finish(std::string_view reason, std::string error = {});

  // Control channel.
  void connect_control();
  void on_control_ready(const std::string& error);
  void on_match_results(const wire::MatchResults& results);
  void on_control_closed(const std::string& reason);
  void sign_in();
  void log_in();
  void on_session(const wire::ServerMessage& reply);
  /// Takes a seat: back in the match the bot holds a seat in, config_.match_id, placement
  /// (find_match), or the first listed match with room.
  void seek_seat();
  void join_listed();
  void join(std::uint32_t match_id);
  void on_join(const wire::ServerMessage& reply);
  /// ALREADY_IN_MATCH: leave the seat this connection holds, then seek one again.
  void leave_then_seek();
  /// A refusal the bot answers by itself (waiting, finding again): told to on_failure_.
  void report_refusal(const std::string& reason);

  // Placement (config_.find_match).
  /// Nothing holds the bot on the server it is connected to: no seat, no ticket for it.
  bool unplaced() const { return wanted_ && match_id_ == 0 && !ticket_; }
  void find_match();
  void on_find_match(const wire::ServerMessage& reply);
  void join_with_ticket();
  /// The ticket's join was refused: what refusal_policy.h says for `reply`.
  void on_ticket_refused(const wire::ServerMessage& reply);
  /// find_match again after a back-off; the bot gives up after kMaxFindAgainInARow in a row.
  void find_again(const std::string& reason);
  void after_match();

  // Game channel.
  void open_game(const wire::JoinMatchReply& reply);
  void on_game_event(proto::ClientEvent& event);
  void on_payload(std::span<const std::uint8_t> bytes, proto::TimeUs now);
  void on_reliable(std::span<const std::uint8_t> bytes);
  /// Adds the current connection's counts (transport, feed) to `out`.
  void add_connection(BotMetrics& out, proto::TimeUs now) const;
  /// On arrival: take the server's scores for our entity where they differ from our count.
  void adopt_scores(const wire::MatchState& state);
  void on_kill(const wire::Kill& kill);
  void on_game_lost(proto::DisconnectReason reason);
  void close_game(bool tell_server);
  void tick();
  void schedule_tick(proto::TimeUs now);
  /// Wraps a handler so that it does nothing once this bot is destroyed.
  template <class Handler>
  auto guarded(Handler handler);

  boost::asio::io_context& io_;
  boost::asio::ssl::context& tls_;
  ServerTrust& trust_;
  BotConfig config_;
  /// Where a control connection goes and how its certificate is trusted.
  struct ServerTarget {
    boost::asio::ip::tcp::endpoint control;
    ServerTrust* trust = nullptr;  ///< trust_, or one of assigned_trust_
    std::uint16_t game_port = 0;   ///< the assignment's; 0: the join reply's udp_port
  };
  ServerTarget home_;  ///< config_.host: where the bot signs in first and asks for a seat
  ServerTarget at_;    ///< the current (or next) control connection's
  /// One pin per assigned server, by fingerprint (node-based: the targets point into it).
  /// The assignment came over a control channel the bot already trusted (its certificate
  /// checked by trust_ or an earlier pin), from the fleet's directory, which each server writes
  /// itself; so pinning the fingerprint it names extends that trust by one hop, to a server the
  /// bot could not otherwise have verified, and trusts nothing a man in the middle chose.
  std::map<std::string, ServerTrust> assigned_trust_;
  boost::asio::ip::address local_address_;  ///< config_.bind_address; unspecified: any
  boost::asio::ip::udp::endpoint game_endpoint_;
  BotState state_ = BotState::Connecting;
  std::function<void()> on_done_;
  std::function<void(std::string_view)> on_failure_;

  std::shared_ptr<ControlClient> control_;
  std::string session_token_;
  bool signed_in_ = false;      ///< on the current control connection
  std::uint32_t match_id_ = 0;  ///< the match the bot is seated in (0: none)
  bool awaiting_results_ = false;
  int failed_attempts_ = 0;
  int busy_retries_ = 0;               ///< SERVER_BUSY in a row at sign-in
  std::optional<MatchWanted> wanted_;  ///< config_.find_match, parsed
  std::optional<Assigned> ticket_;     ///< an assignment not yet presented
  int find_again_ = 0;                 ///< tickets refused in a row (refusal_policy.h)
  /// When this placement's first find_match was sent (steady us); -1: not placing.
  proto::TimeUs finding_since_us_ = -1;
  std::minstd_rand retry_random_;  ///< spreads the busy retries of bots refused together

  std::shared_ptr<SharedGamePort> shared_port_;  ///< null: a socket per game connection
  std::shared_ptr<GameSession> game_;
  std::optional<GameFeed> feed_;  ///< the current game connection's
  /// The current connection's interpolation and prediction; empty in cheap mode (predict off).
  std::optional<RenderedView> rendered_;
  std::unique_ptr<StateDump> dump_;  ///< config_.dump_states, from start(); null: none
  Brain brain_;
  bool arrived_ = false;          ///< the first MatchState of this connection was seen
  bool entity_recorded_ = false;  ///< this connection's entity is in record_.entity_ids
  /// From payloads, or our own PlayerJoined before the first; kept across reconnects.
  std::uint32_t own_entity_id_ = 0;
  bool match_over_ = false;
  std::uint32_t tick_rate_hz_ = 60;
  proto::TimeUs tick_period_us_ = 16'667;
  proto::TimeUs next_tick_us_ = 0;
  proto::TimeUs connected_at_us_ = 0;
  proto::TimeUs lost_at_us_ = -1;
  proto::TimeUs next_rtt_sample_us_ = 0;
  /// The match phase from MatchState events, kept across reconnects (a new connection's
  /// arrival does not change it).
  wire::MatchPhase phase_ = wire::MATCH_PHASE_UNSPECIFIED;
  // This match's running phase as the bot counted it from Kill events.
  int match_kills_ = 0;
  int match_deaths_ = 0;
  int score_counted_ = 0;

  proto::TimeUs started_at_us_ = 0;
  BotMetrics metrics_;
  BotRecord record_;
  boost::asio::steady_timer deadline_;
  boost::asio::steady_timer tick_timer_;
  std::shared_ptr<bool> alive_;  ///< handlers hold a weak_ptr: a destroyed bot is not touched
};

}  // namespace ricochet::bot
