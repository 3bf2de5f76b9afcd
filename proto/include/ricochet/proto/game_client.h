#pragma once
/// The client end of the game channel as a sans-IO state machine (PROTOCOL.md Game channel
/// transport): SendingRequest → SendingResponse → Connected → Disconnected(reason). Used by the bot
/// client and the tests. One GameClient per connect token; a reconnect takes a new token and a new
/// GameClient. Not thread-safe.

#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <span>
#include <variant>
#include <vector>

#include "ricochet/proto/address.h"
#include "ricochet/proto/clock.h"
#include "ricochet/proto/token_grant.h"
#include "ricochet/proto/transmit.h"
#include "ricochet/proto/transport_counters.h"

namespace ricochet::proto {

struct ClientConnectInfo {
  TokenGrant grant;  ///< from the control channel's join reply
  std::uint64_t protocol_id = 0;
  Address server;  ///< the game channel's address (UDP 7778)
};

struct GameClientConfig {
  TimeUs resend_us = 100 * kMicrosPerMilli;      ///< request and response resend, 10 Hz
  TimeUs keep_alive_us = 100 * kMicrosPerMilli;  ///< 10 Hz when idle
  TimeUs reliable_resend_us = 100 * kMicrosPerMilli;
  std::size_t max_reliable_pending = 256;
  TransportLog log;
};

struct ClientConnected {};
struct ClientDisconnected {
  DisconnectReason reason = DisconnectReason::Requested;
};
struct ClientUnreliable {
  std::vector<std::uint8_t> bytes;
};
struct ClientReliable {
  std::vector<std::uint8_t> bytes;
};
using ClientEvent =
    std::variant<ClientConnected, ClientDisconnected, ClientUnreliable, ClientReliable>;

class GameClient {
 public:
  /// Queues the first connection request at once.
  GameClient(ClientConnectInfo info, TimeUs now, GameClientConfig config = {});
  ~GameClient();
  GameClient(const GameClient&) = delete;
  GameClient& operator=(const GameClient&) = delete;

  /// One untrusted datagram; anything not from the server's address is dropped.
  void receive(const Address& from, std::span<const std::uint8_t> datagram, TimeUs now);
  /// Resends the request or response, keep-alives, reliable resends, timeouts.
  void update(TimeUs now);
  /// The next datagram to send into `out`; the client keeps `out`'s previous buffer for a later
  /// datagram (as GameServer::poll_transmit does).
  bool poll_transmit(Transmit& out);
  bool poll_event(ClientEvent& out);

  /// Connected only: one payload packet (≤ kMaxUnreliableBytes) with any reliable messages due.
  bool send_unreliable(std::span<const std::uint8_t> payload, TimeUs now);
  /// Queued until connected and sent with the next payload or update(). False when the message
  /// is empty or too large, when disconnected, or when the queue is full (then disconnects).
  bool send_reliable(std::span<const std::uint8_t> message, TimeUs now);
  /// The one exit: tells the server when connected (three disconnect packets).
  void disconnect(TimeUs now);

  ConnectionState state() const;
  /// Set once Disconnected.
  std::optional<DisconnectReason> disconnect_reason() const;
  TimeUs rtt_us() const;
  const TransportCounters& counters() const;

  /// The server's packets on this connection, by sequence: every packet it sends (payload,
  /// keep-alive, disconnect) takes the next one, so missing / sent is the link's loss towards
  /// the client, whatever the packets carried (a tick without a snapshot is not a loss).
  struct ReceiveStats {
    std::uint64_t sent = 0;     ///< the newest sequence accepted + 1; 0 before any
    std::uint64_t missing = 0;  ///< of those, never accepted (lost, or too late for the window)
    std::uint64_t late = 0;     ///< accepted after a newer one
  };
  ReceiveStats receive_stats() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace ricochet::proto
