#include "ricochet/proto/transport_counters.h"

#include <numeric>

namespace ricochet::proto {

std::string_view name(DropReason reason) {
  switch (reason) {
    case DropReason::Empty:
      return "empty";
    case DropReason::Oversized:
      return "oversized";
    case DropReason::Truncated:
      return "truncated";
    case DropReason::Malformed:
      return "malformed";
    case DropReason::WrongVersion:
      return "wrong_version";
    case DropReason::WrongProtocol:
      return "wrong_protocol";
    case DropReason::WrongState:
      return "wrong_state";
    case DropReason::UnknownAddress:
      return "unknown_address";
    case DropReason::ForgedMac:
      return "forged_mac";
    case DropReason::Replayed:
      return "replayed";
    case DropReason::TokenInvalid:
      return "token_invalid";
    case DropReason::TokenExpired:
      return "token_expired";
    case DropReason::TokenReused:
      return "token_reused";
    case DropReason::ChallengeInvalid:
      return "challenge_invalid";
    case DropReason::AddressRateLimited:
      return "address_rate_limited";
    case DropReason::ClientRateLimited:
      return "client_rate_limited";
    case DropReason::AddressTableFull:
      return "address_table_full";
    case DropReason::HalfOpenCap:
      return "half_open_cap";
    case DropReason::ServerFull:
      return "server_full";
    case DropReason::ReliableOutOfWindow:
      return "reliable_out_of_window";
    case DropReason::HandshakeInProgress:
      return "handshake_in_progress";
    case DropReason::HostHalfOpenCap:
      return "host_half_open_cap";
    case DropReason::HostFull:
      return "host_full";
    case DropReason::UsedTokenTableFull:
      return "used_token_table_full";
  }
  return "unknown";
}

std::string_view name(DisconnectReason reason) {
  switch (reason) {
    case DisconnectReason::Requested:
      return "requested";
    case DisconnectReason::PeerRequested:
      return "peer_requested";
    case DisconnectReason::TimedOut:
      return "timed_out";
    case DisconnectReason::HandshakeTimedOut:
      return "handshake_timed_out";
    case DisconnectReason::Denied:
      return "denied";
    case DisconnectReason::Replaced:
      return "replaced";
    case DisconnectReason::ReliableOverflow:
      return "reliable_overflow";
    case DisconnectReason::ServerShutdown:
      return "server_shutdown";
    case DisconnectReason::Kicked:
      return "kicked";
    case DisconnectReason::HostFull:
      return "host_full";
    case DisconnectReason::Left:
      return "left";
    case DisconnectReason::Banned:
      return "banned";
  }
  return "unknown";
}

std::string_view name(ConnectionState state) {
  switch (state) {
    case ConnectionState::Connecting:
      return "connecting";
    case ConnectionState::Challenged:
      return "challenged";
    case ConnectionState::SendingRequest:
      return "sending_request";
    case ConnectionState::SendingResponse:
      return "sending_response";
    case ConnectionState::Connected:
      return "connected";
    case ConnectionState::Disconnected:
      return "disconnected";
  }
  return "unknown";
}

std::uint64_t TransportCounters::dropped_total() const {
  return std::accumulate(drops.begin(), drops.end(), std::uint64_t{0});
}

}  // namespace ricochet::proto
