#pragma once
/// One game connection over a real UDP socket: proto::GameClient (the sans-IO client end of the
/// game channel) driven by an io_context, on a socket of its own bound to a fresh local port.
/// It reads the clock only where IO happens and passes that time into the transport.
/// A reconnect (new token, or a new address) is a new GameSession. With an active LinkConfig
/// every datagram each way goes through a LinkSimulator (its own seeded generator per
/// direction), released by a timer when due.

#include <array>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "ricochet/bot/link_simulator.h"
#include "ricochet/bot/shared_game_port.h"
#include "ricochet/proto/clock.h"
#include "ricochet/proto/game_client.h"

namespace ricochet::bot {

/// The io layer's clock: steady, in µs.
proto::TimeUs steady_now_us();

/// The transport's view of a UDP endpoint.
proto::Address to_address(const boost::asio::ip::udp::endpoint& endpoint);

class GameSession : public std::enable_shared_from_this<GameSession> {
 public:
  using EventHandler = std::function<void(proto::ClientEvent& event)>;

  /// Binds a new socket (any free port on the local address of the server's family); the
  /// connection request goes out at once (through the link, when one is simulated). `link`
  /// must be valid; `link_seed` seeds its generators.
  GameSession(boost::asio::io_context& io, const boost::asio::ip::udp::endpoint& server,
              proto::TokenGrant grant, EventHandler on_event, const LinkConfig& link = {},
              std::uint64_t link_seed = 1);
  GameSession(const GameSession&) = delete;
  GameSession& operator=(const GameSession&) = delete;

  /// Moves the socket to any free port on `local` (an address of the server's family); before
  /// start() only. Empty on success, else why the socket could not be bound.
  std::string bind_local(const boost::asio::ip::address& local);
  /// Moves the game channel onto `port` (one socket shared by many bots), from a fresh address
  /// of its own; before start() only. Empty on success, else why not.
  std::string use_shared_port(std::shared_ptr<SharedGamePort> port);
  /// A datagram the shared port read for this session.
  void receive_datagram(const boost::asio::ip::udp::endpoint& from,
                        std::span<const std::uint8_t> bytes, proto::TimeUs now);
  /// Starts reading datagrams.
  void start();
  /// Resends, keep-alives and timeouts; call at least every 100 ms.
  void update(proto::TimeUs now);
  /// One unreliable payload (Connected only); false when it was not sent.
  bool send(std::span<const std::uint8_t> payload, proto::TimeUs now);
  /// Tells the server (three disconnect packets) when connected, then closes the socket.
  void disconnect(proto::TimeUs now);
  /// Closes the socket without a word to the server (what an address change looks like).
  void abandon();

  proto::ConnectionState state() const { return client_.state(); }
  const proto::GameClient& transport() const { return client_; }
  std::uint16_t local_port() const { return local_port_; }
  /// Datagrams the socket could not send at once (full buffer); they are lost.
  std::uint64_t send_failures() const { return send_failures_; }
  /// The simulated link's counters, client to server and back (zero without one).
  LinkCounters link_up() const { return up_ ? up_->counters() : LinkCounters{}; }
  LinkCounters link_down() const { return down_ ? down_->counters() : LinkCounters{}; }

 private:
  void wait_readable();
  void drain(proto::TimeUs now);
  /// One datagram from the socket: into the simulated downlink when there is one, else to the
  /// transport.
  void take(const boost::asio::ip::udp::endpoint& from, std::span<const std::uint8_t> bytes,
            proto::TimeUs now);
  void send_queued(proto::TimeUs now);
  /// Sends what the transport queued, then hands its events to on_event_.
  void flush(proto::TimeUs now);
  /// One datagram out of the socket, now (or queued on the shared port for this loop turn).
  void transmit(std::span<const std::uint8_t> bytes);
  /// Moves what the simulated links have due by `now` on, and re-arms the link timer.
  void pump_links(proto::TimeUs now);

  boost::asio::ip::udp::socket socket_;  ///< closed when shared_port_ carries the channel
  std::shared_ptr<SharedGamePort> shared_port_;
  boost::asio::ip::address_v4 shared_address_;  ///< this session's source on shared_port_
  boost::asio::ip::udp::endpoint server_;
  proto::GameClient client_;
  proto::Transmit outgoing_;  ///< polled into and kept, so its buffer is reused
  EventHandler on_event_;
  std::array<std::uint8_t, 2048> buffer_{};
  std::uint16_t local_port_ = 0;
  std::uint64_t send_failures_ = 0;
  bool closed_ = false;
  std::optional<LinkSimulator> up_;    ///< client to server
  std::optional<LinkSimulator> down_;  ///< server to client
  boost::asio::steady_timer link_timer_;
  proto::TimeUs link_armed_for_ = -1;  ///< the due time the timer waits for; -1: idle
};

}  // namespace ricochet::bot
