#pragma once
/// The game channel's named states, the reasons it drops packets and ends connections, and the
/// counters it keeps (PROTOCOL.md Game channel transport §states, §rejections). Every drop is
/// counted by reason; every state transition is reported once, with its reason, through a log
/// callback.

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string_view>

#include "ricochet/proto/address.h"

namespace ricochet::proto {

/// Handle of a connected client on one GameServer. Never reused within a server's lifetime, so a
/// stale id names no client instead of the wrong one. 0 is "no client".
using ClientId = std::uint32_t;

/// Why an incoming datagram was dropped. Wire-visible behaviour: a dropped packet gets no reply.
enum class DropReason : std::uint8_t {
  Empty,                ///< zero bytes
  Oversized,            ///< more than kMaxDatagramBytes
  Truncated,            ///< shorter than its packet type needs
  Malformed,            ///< unknown type, bad length field or body that does not parse
  WrongVersion,         ///< connection request with another version string
  WrongProtocol,        ///< connection request with another protocol id
  WrongState,           ///< packet type not allowed in the sender's connection state
  UnknownAddress,       ///< encrypted packet from an address with no handshake or connection
  ForgedMac,            ///< authentication tag does not verify (wrong key, tampered, forged)
  Replayed,             ///< sequence already received or older than the 256-entry window
  TokenInvalid,         ///< connect token does not open under the server key, or bad contents
  TokenExpired,         ///< connect token past its expiry on the server's clock
  TokenReused,          ///< connect token already used from another address, or already connected
  ChallengeInvalid,     ///< response whose challenge token does not open: spoofed source
  AddressRateLimited,   ///< per-address packet budget for unconnected senders exhausted
  ClientRateLimited,    ///< per-client packet budget for a connected client exhausted
  AddressTableFull,     ///< too many unconnected addresses tracked for rate limiting
  HalfOpenCap,          ///< too many handshakes in progress
  ServerFull,           ///< max_clients connected; answered with a denied packet
  ReliableOutOfWindow,  ///< reliable message id too far ahead of the next expected one
  HandshakeInProgress,  ///< request with another account's token from an address mid-handshake
  HostHalfOpenCap,      ///< too many handshakes in progress from the sender's host (host_key)
  HostFull,             ///< max_clients_per_host connected from that host; answered with denied
  UsedTokenTableFull,   ///< the table of used tokens is at its cap: no new handshake for now
};
inline constexpr std::size_t kDropReasonCount =
    static_cast<std::size_t>(DropReason::UsedTokenTableFull) + 1;
std::string_view name(DropReason reason);

/// Why a connection ended. Carried in the disconnect and denied packets (one byte).
enum class DisconnectReason : std::uint8_t {
  Requested,          ///< this end's application asked for it
  PeerRequested,      ///< the other end sent a disconnect packet
  TimedOut,           ///< no valid packet for the token's timeout
  HandshakeTimedOut,  ///< client: no challenge or no keep-alive within the timeout
  Denied,             ///< denied: server full
  Replaced,           ///< the same account connected again (new token, maybe a new address)
  ReliableOverflow,   ///< must-arrive reliable messages passed their cap: the peer stopped acking
  ServerShutdown,     ///< the server is stopping
  Kicked,             ///< the server's application removed the client
  HostFull,           ///< denied: too many clients from the client's host (host_key)
  Left,               ///< the player left its match (LeaveMatch on the control channel)
  Banned,             ///< an operator banned the player's account
};
inline constexpr std::size_t kDisconnectReasonCount =
    static_cast<std::size_t>(DisconnectReason::Banned) + 1;
std::string_view name(DisconnectReason reason);

/// Connection states. Server side per address: Connecting → Challenged → Connected →
/// Disconnected (the app's InMatch sits inside Connected). Client side: SendingRequest →
/// SendingResponse → Connected → Disconnected.
enum class ConnectionState : std::uint8_t {
  Connecting,
  Challenged,
  SendingRequest,
  SendingResponse,
  Connected,
  Disconnected,
};
inline constexpr std::size_t kConnectionStateCount =
    static_cast<std::size_t>(ConnectionState::Disconnected) + 1;
std::string_view name(ConnectionState state);

/// One state transition of one connection, reported exactly once.
struct StateTransition {
  Address address;      ///< the peer (the server's address on the client side)
  ClientId client = 0;  ///< 0 before the connection has an id, and on the client side
  ConnectionState from = ConnectionState::Connecting;
  ConnectionState to = ConnectionState::Connecting;
  std::string_view reason;  ///< static text, e.g. "valid connection request"
};

/// Where endpoints report. Both callbacks are optional; the server layer logs transitions at
/// info and drops at debug level.
struct TransportLog {
  std::function<void(const StateTransition&)> on_transition;
  std::function<void(DropReason, const Address&)> on_drop;
};

struct TransportCounters {
  std::uint64_t packets_in = 0;
  std::uint64_t packets_out = 0;
  std::uint64_t bytes_in = 0;
  std::uint64_t bytes_out = 0;
  std::array<std::uint64_t, kDropReasonCount> drops{};
  std::array<std::uint64_t, kDisconnectReasonCount> disconnects{};
  std::uint64_t connections_total = 0;  ///< handshakes completed
  std::uint64_t reliable_resends = 0;   ///< reliable messages sent again for want of an ack
  std::uint64_t reliable_dropped = 0;   ///< droppable reliable messages a client had no room for
  std::uint32_t half_open = 0;          ///< handshakes in progress now (gauge)
  std::uint32_t connected = 0;          ///< connected clients now (gauge)

  std::uint64_t dropped(DropReason reason) const { return drops[static_cast<std::size_t>(reason)]; }
  std::uint64_t dropped_total() const;
};

}  // namespace ricochet::proto
