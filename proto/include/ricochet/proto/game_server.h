#pragma once
/// The server end of the game channel as a sans-IO state machine (PROTOCOL.md Game channel
/// transport): bytes and time in, datagrams and events out. It knows no socket and reads no clock.
///
/// Use: for every datagram call receive(); call update() at least every keep-alive interval
/// (10 ms..100 ms); after every call drain poll_transmit() into the socket and poll_event()
/// into the application. Not thread-safe: one thread owns a GameServer.

#include <cstdint>
#include <deque>
#include <memory>
#include <span>
#include <string>
#include <unordered_map>
#include <variant>
#include <vector>

#include "ricochet/proto/address.h"
#include "ricochet/proto/clock.h"
#include "ricochet/proto/reliable_channel.h"
#include "ricochet/proto/token_grant.h"
#include "ricochet/proto/transmit.h"
#include "ricochet/proto/transport_counters.h"

namespace ricochet::proto {

struct GameServerConfig {
  std::uint64_t protocol_id = 0;     ///< must match the tokens' and the clients'
  Key token_key{};                   ///< server-only key the connect tokens are sealed with
  int max_clients = 64;              ///< connected at once; more get a denied packet
  int max_half_open = 256;           ///< handshakes in progress at once; more are dropped
  int max_tracked_addresses = 4096;  ///< unconnected addresses with a rate-limit bucket
  /// Per host (proto::host_key: an IPv4 address, or an IPv6 /64), so that one source cannot
  /// take every slot: handshakes in progress (more are dropped) and connected clients (more get
  /// a denied packet with reason HostFull).
  int max_half_open_per_host = 16;
  int max_clients_per_host = 32;
  /// Tokens remembered from valid requests until they expire (PROTOCOL.md §connect token: a
  /// token opens one handshake). When full, new requests are dropped, never a token forgotten.
  int max_used_tokens = 65536;
  double address_packets_per_s = 20.0;  ///< budget of an unconnected address
  double address_burst = 20.0;
  double client_packets_per_s = 250.0;  ///< budget of a connected client
  double client_burst = 250.0;
  TimeUs keep_alive_us = 100 * kMicrosPerMilli;       ///< 10 Hz when idle
  TimeUs reliable_resend_us = 100 * kMicrosPerMilli;  ///< resend an unacked reliable message
  std::size_t max_reliable_pending = 256;  ///< 1..256 reliable messages in flight per client
  /// max_reliable_pending..65536 held per client, in flight or waiting: a must-arrive message
  /// beyond it disconnects (ReliableOverflow); droppable ones stop at max_reliable_pending / 2.
  std::size_t max_reliable_queued = 1024;
  TransportLog log;

  /// Empty when valid, else what is wrong, e.g. "max_clients must be 1..4096, got 0".
  std::string validate() const;
};

struct ServerConnected {
  ClientId client = 0;
  std::uint64_t account_id = 0;
  std::uint32_t match_id = 0;
  Address address;
};
struct ServerDisconnected {
  ClientId client = 0;
  std::uint64_t account_id = 0;
  DisconnectReason reason = DisconnectReason::Requested;
};
struct ServerUnreliable {
  ClientId client = 0;
  std::vector<std::uint8_t> bytes;
  std::uint64_t account_id = 0;  ///< the client's, so the application needs no lookup
  TimeUs rtt_us = 0;             ///< the client's round-trip estimate when the packet came
};
struct ServerReliable {
  ClientId client = 0;
  std::vector<std::uint8_t> bytes;
};
using ServerEvent =
    std::variant<ServerConnected, ServerDisconnected, ServerUnreliable, ServerReliable>;

class GameServer {
 public:
  /// Makes the challenge key. Throws std::invalid_argument with validate()'s text.
  explicit GameServer(GameServerConfig config);
  ~GameServer();
  GameServer(const GameServer&) = delete;
  GameServer& operator=(const GameServer&) = delete;

  /// One untrusted datagram from `from`. Never throws on bad input: drops and counts it.
  void receive(const Address& from, std::span<const std::uint8_t> datagram, TimeUs now);
  /// Timeouts (handshakes and clients), keep-alives when idle, reliable resends.
  void update(TimeUs now);
  /// The next datagram to send into `out`. The server keeps `out`'s previous buffer for a later
  /// datagram, so a caller that reuses its Transmits sends without allocating.
  bool poll_transmit(Transmit& out);
  bool poll_event(ServerEvent& out);

  /// One payload packet with `payload` (≤ kMaxUnreliableBytes) and any reliable messages due that
  /// fit. False when the client is unknown or the payload too large.
  bool send_unreliable(ClientId client, std::span<const std::uint8_t> payload, TimeUs now);
  /// Queued; sent with the next payload or by update(). False when the client is unknown, the
  /// message empty or larger than kMaxReliableMessageBytes, or refused by `delivery`
  /// (reliable_channel.h): a Droppable message the client has no room for is dropped and counted
  /// (TransportCounters::reliable_dropped); a MustArrive one beyond max_reliable_queued
  /// disconnects the client (ReliableOverflow).
  bool send_reliable(ClientId client, std::span<const std::uint8_t> message, TimeUs now,
                     Delivery delivery = Delivery::MustArrive);
  /// The one exit: tells the client (three disconnect packets), reports ServerDisconnected.
  void disconnect(ClientId client, DisconnectReason reason, TimeUs now);
  void disconnect_all(DisconnectReason reason, TimeUs now);

  bool connected(ClientId client) const;
  std::size_t client_count() const;
  /// Smoothed round trip of a client in µs (0 when unknown or not yet measured).
  TimeUs rtt_us(ClientId client) const;
  const TransportCounters& counters() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace ricochet::proto
