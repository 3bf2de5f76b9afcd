#pragma once
/// The game channel's socket layer: one UDP socket and the sans-IO proto::GameServer on one
/// strand. Datagrams go into the GameServer; what it wants sent goes out of the socket; its
/// events go to a GameRouter (the match registry), which hands them to the matches' strands.
/// Matches send back through send(), which posts to this strand.
///
///   socket ─receive─▶ GameServer ─events─▶ GameRouter ─post─▶ match strands
///   socket ◀─send_to─ GameServer ◀─send()── match strands
///
/// The game server keys connections by account: one connection per account (a new one replaces
/// the old, which is how a client that changed address comes back).

#include <atomic>
#include <boost/asio/awaitable.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <boost/unordered/unordered_flat_map.hpp>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "datagram_batch.h"
#include "ricochet/proto/game_server.h"
#include "ricochet/server/match.h"

namespace ricochet::server {

/// A game payload of a connected account, as the channel hands it on.
struct GamePayload {
  std::uint64_t account = 0;
  std::vector<std::uint8_t> bytes;
  /// The connection's smoothed round trip (GameServer::rtt_us; 0 until measured).
  proto::TimeUs rtt_us = 0;
};

/// Where the game channel's events go. Called on the channel's strand; implementations post
/// onward and return at once.
class GameRouter {
 public:
  virtual ~GameRouter() = default;
  virtual void connected(std::uint64_t account, std::uint32_t match_id) = 0;
  virtual void disconnected(std::uint64_t account, proto::DisconnectReason reason) = 0;
  /// The payloads of one wake-up of the channel, in the order they came (and after every
  /// connected or disconnected event that came before them), so that each match can be handed
  /// its players' inputs at once.
  virtual void payloads(std::vector<GamePayload> batch) = 0;
  virtual void reliable(std::uint64_t account, std::vector<std::uint8_t> bytes) = 0;
};

struct GameChannelConfig {
  std::string bind = "0.0.0.0";  ///< IP address literal
  std::uint16_t port = 7778;     ///< 0: any free port
  proto::GameServerConfig transport;
  proto::TimeUs update_interval_us = 10 * proto::kMicrosPerMilli;  ///< timeouts, keep-alives
};

class GameChannel {
 public:
  /// Validates the transport config (std::invalid_argument). Binds nothing yet.
  GameChannel(boost::asio::io_context& io, GameChannelConfig config);
  ~GameChannel();
  GameChannel(const GameChannel&) = delete;
  GameChannel& operator=(const GameChannel&) = delete;

  /// Binds and starts receiving, handing events to `router` (which outlives the channel's
  /// run); throws boost::system::system_error when it cannot bind.
  void start(GameRouter& router);
  /// Tells every client (ServerShutdown), sends what is queued, closes the socket. Thread-safe;
  /// `done` runs on the channel's strand once the socket is closed.
  void stop(std::function<void()> done = {});

  /// Thread-safe: queue bytes for the account's connection (dropped when it has none).
  void send(std::uint64_t account, bool reliable, std::vector<std::uint8_t> bytes);
  /// Thread-safe: send() of each, in order, with one post (a match's tick) and the datagrams
  /// leaving in as few sendmmsg calls as fit.
  void send_all(std::vector<Outgoing> messages);
  /// Thread-safe: ends the account's connection (the one exit, with its reason), after sending
  /// the reliable messages queued for it (a match's MatchEnded) once.
  void kick(std::uint64_t account, proto::DisconnectReason reason);

  std::uint16_t port() const { return port_.load(); }
  /// A copy of the transport's counters, refreshed on every update (thread-safe).
  proto::TransportCounters counters() const;

 private:
  boost::asio::awaitable<void> receive_loop();
  boost::asio::awaitable<void> update_loop();
  /// Drains the GameServer's events and datagrams after every call into it.
  void drain();
  /// Reads every datagram waiting (bounded per wake-up) into the GameServer.
  void receive_waiting();
  void publish_counters();

  GameChannelConfig config_;
  GameRouter* router_ = nullptr;
  boost::asio::strand<boost::asio::io_context::executor_type> strand_;
  boost::asio::ip::udp::socket socket_;
  boost::asio::steady_timer update_timer_;
  proto::GameServer transport_;
  DatagramReceiver receiver_;
  DatagramSender sender_;
  /// Open addressing: a lookup for every datagram sent is one probe of a flat array instead of
  /// a bucket and a node in two cold places.
  boost::unordered_flat_map<std::uint64_t, proto::ClientId> client_of_account_;
  boost::unordered_flat_map<proto::ClientId, std::uint64_t> account_of_client_;
  bool stopping_ = false;
  std::atomic<std::uint16_t> port_{0};
  mutable std::mutex counters_mutex_;
  proto::TransportCounters published_;
};

}  // namespace ricochet::server
