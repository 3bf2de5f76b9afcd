#pragma once
/// Which packet types each connection state accepts (PROTOCOL.md Game channel transport §states).
/// The one place both endpoints check; a packet outside its state is dropped as WrongState.
///
///   server, per address        accepts
///   Connecting (no entry)      connection request
///   Challenged                 connection request (challenge resent), response
///   Connected                  response (keep-alive resent), keep-alive, payload, disconnect
///
///   client                     accepts
///   SendingRequest             denied, challenge
///   SendingResponse            denied, challenge (ignored), keep-alive, payload, disconnect
///   Connected                  keep-alive, payload, disconnect
///   Disconnected               nothing

#include "ricochet/proto/packet.h"
#include "ricochet/proto/transport_counters.h"

namespace ricochet::proto {

constexpr bool server_accepts(ConnectionState state, PacketType type) {
  switch (state) {
    case ConnectionState::Connecting:
      return type == PacketType::ConnectionRequest;
    case ConnectionState::Challenged:
      return type == PacketType::ConnectionRequest || type == PacketType::Response;
    case ConnectionState::Connected:
      return type == PacketType::Response || type == PacketType::KeepAlive ||
             type == PacketType::Payload || type == PacketType::Disconnect;
    default:
      return false;
  }
}

constexpr bool client_accepts(ConnectionState state, PacketType type) {
  switch (state) {
    case ConnectionState::SendingRequest:
      return type == PacketType::ConnectionDenied || type == PacketType::Challenge;
    case ConnectionState::SendingResponse:
      return type == PacketType::ConnectionDenied || type == PacketType::Challenge ||
             type == PacketType::KeepAlive || type == PacketType::Payload ||
             type == PacketType::Disconnect;
    case ConnectionState::Connected:
      return type == PacketType::KeepAlive || type == PacketType::Payload ||
             type == PacketType::Disconnect;
    default:
      return false;
  }
}

}  // namespace ricochet::proto
