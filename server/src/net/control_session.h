#pragma once
/// One control connection: the TLS handshake, then frames read, validated and dispatched to the
/// DB worker or the match directory, replies written back, every deadline watched. Runs on the
/// control server's strand; every member function is called there.
///
///   run():    handshake ─▶ read loop (frames ─▶ parse ─▶ rate ─▶ state table ─▶ dispatch ─▶ reply)
///   writer:   drains the outbox; after close() it flushes the final Error, then closes
///   watchdog: handshake, frame (slowloris), idle and write deadlines; the close grace
///             (control_deadlines.h decides which is next; the clock is the context's)

#include <array>
#include <boost/asio/awaitable.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/asio/steady_timer.hpp>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_set>
#include <vector>

#include "control_config.h"
#include "control_counters.h"
#include "control_deadlines.h"
#include "episode_log.h"
#include "match_directory.h"
#include "ricochet/db/db_worker.h"
#include "ricochet/proto/control_states.h"
#include "ricochet/proto/frame.h"
#include "ricochet/proto/token_bucket.h"
#include "ricochet/wire/control.pb.h"

namespace ricochet::server {

/// What every session of one server shares; owned by the ControlServer.
struct ControlContext {
  const ControlLimits& limits;
  ControlCounters& counters;
  db::DbWorker& db;
  MatchDirectory& matches;
  /// The server's clock in µs (ControlServerConfig::clock): deadlines, the message rate and
  /// connect tokens' expiry.
  std::function<proto::TimeUs()> clock;
  /// Logs the account refusals once per episode (ControlServerConfig::episodes); may be null.
  EpisodeLog* episodes;
  /// Accounts banned while this server ran (ControlServer::ban_account): a login or resume the
  /// database let through just before the ban is refused when it completes. On the strand.
  std::unordered_set<std::uint64_t> banned;
  /// Placement across the fleet (find_match, tickets); nullptr when off on this server.
  FleetPlacement* placement;
};

class ControlSession : public std::enable_shared_from_this<ControlSession> {
 public:
  using Stream = boost::asio::ssl::stream<boost::asio::ip::tcp::socket>;
  /// Called once on the strand when the session has ended and its socket is closed.
  using OnEnded = std::function<void(ControlSession&)>;

  /// `address` is the peer's IP (text), for logs and the per-address cap; the login and
  /// registration limits count under its proto::host_key.
  ControlSession(std::uint64_t id, boost::asio::ip::tcp::socket socket,
                 boost::asio::ssl::context& tls, std::string address, ControlContext& context,
                 OnEnded on_ended);
  ControlSession(const ControlSession&) = delete;
  ControlSession& operator=(const ControlSession&) = delete;

  /// The whole life of the connection; co_spawn it on the strand.
  boost::asio::awaitable<void> run();
  /// Queues a server-initiated message (request_id 0). MatchResults also ends InMatch.
  void push(wire::ServerMessage message);
  /// Sends an Error (request_id 0) and closes once it is written (or the grace is over).
  void close(wire::ErrorCode code, const std::string& message, std::string_view reason);
  /// Wakes the watchdog to compare the deadlines with the clock now, not only when its timer
  /// fires: after a deadline moved, or the clock moved other than in real time.
  void check_deadlines();

  std::uint64_t id() const { return id_; }
  const std::string& address() const { return address_; }
  std::uint64_t account() const { return account_; }
  proto::ControlState state() const { return machine_.state(); }

 private:
  boost::asio::awaitable<bool> handshake();
  boost::asio::awaitable<void> read_loop();
  boost::asio::awaitable<void> write_loop(std::shared_ptr<ControlSession> self);
  boost::asio::awaitable<void> watch(std::shared_ptr<ControlSession> self);
  /// Handles every whole frame buffered in the reader.
  boost::asio::awaitable<void> drain_frames();
  boost::asio::awaitable<void> handle(const std::vector<std::uint8_t>& payload);
  boost::asio::awaitable<wire::ServerMessage> dispatch(const wire::ClientMessage& message);

  boost::asio::awaitable<wire::ServerMessage> register_account(const wire::RegisterRequest& r);
  boost::asio::awaitable<wire::ServerMessage> login(const wire::LoginRequest& r);
  boost::asio::awaitable<wire::ServerMessage> resume(const wire::ResumeRequest& r);
  boost::asio::awaitable<wire::ServerMessage> logout();
  wire::ServerMessage list_matches();
  wire::ServerMessage create_match(const wire::CreateMatchRequest& r);
  /// A direct join, or one with a ticket (claimed in the database first).
  boost::asio::awaitable<wire::ServerMessage> join_match(const wire::JoinMatchRequest& r);
  /// Seats the account in `match_id`; `placed`: by a ticket, whose seat the held ones include.
  wire::ServerMessage join_seat(std::uint32_t match_id, bool placed);
  /// A claimed ticket's match: the one it names while this server hosts it, else this server's
  /// fullest open match of its mode (and map) with a seat free, else a new one.
  DirectoryResult<std::uint32_t> placed_match(const db::ClaimedTicket& ticket);
  boost::asio::awaitable<wire::ServerMessage> find_match(const wire::FindMatchRequest& r);
  wire::ServerMessage leave_match();
  wire::ServerMessage chat(const wire::ChatRequest& r);
  wire::ServerMessage pong(const wire::Ping& r);

  /// Frames and queues one message; closes the connection when the outbox is over its cap.
  void send(const wire::ServerMessage& message);
  void reply_error(std::uint32_t request_id, wire::ErrorCode code, const std::string& message);
  /// Counts and logs a refusal.
  void refuse(ControlRefusal refusal, const std::string& detail);
  /// The reply to a login, resume or registration the database refused; counts its limits and
  /// SERVER_BUSY (ControlRefusal::ServerBusy).
  wire::ServerMessage account_refusal(const db::DbError& error, ControlRefusal rate_limited);
  /// Logged in or resumed as `account` with `token`: no login deadline any more.
  void authenticated(std::uint64_t account, std::string username, std::string token,
                     std::string_view how);
  /// A stream the FrameReader or the parser refused: Error, then close.
  void refuse_frame(proto::FrameRefusal refusal);

  void begin_closing(std::string_view reason);
  /// Closes the socket now (pending reads and writes end with an error).
  void abort(std::string_view reason);
  /// Starts or clears the frame deadline after the reader's buffer changed.
  void note_partial_frame(proto::TimeUs now);
  void expire(ControlExpiry expiry);
  /// One of the reader and writer tasks ended; the last one ends the session.
  void task_ended();

  std::uint64_t id_;
  Stream stream_;
  std::string address_;
  std::string host_key_;  ///< proto::host_key(address_): what the account limits count under
  ControlContext& context_;
  OnEnded on_ended_;
  proto::ControlStateMachine machine_;
  proto::FrameReader reader_;
  std::vector<std::uint8_t> read_buffer_;
  std::deque<std::vector<std::uint8_t>> outbox_;
  std::size_t outbox_bytes_ = 0;
  boost::asio::steady_timer watchdog_;
  boost::asio::steady_timer outbox_signal_;
  ControlTimes times_;  ///< the phase and what the deadlines count from
  int running_tasks_ = 0;
  bool socket_closed_ = false;
  proto::TokenBucket rate_;  ///< limits.messages_per_second in bursts of limits.message_burst
  std::uint64_t account_ = 0;
  std::string username_;
  std::string session_token_;  ///< the one this connection signed in with; logout revokes it
};

}  // namespace ricochet::server
