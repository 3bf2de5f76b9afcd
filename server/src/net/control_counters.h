#pragma once
/// What the control channel counts, for /metrics: connections by state, traffic, and every
/// refusal by reason. Written on the control server's strand, read from any thread.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>

#include "ricochet/proto/control_states.h"

namespace ricochet::server {

/// Why a connection, frame or message was refused. Each is counted and logged at debug.
enum class ControlRefusal : std::uint8_t {
  ConnectionCap,       ///< max_connections open: closed at accept
  AddressCap,          ///< max_connections_per_address from this IP: closed at accept
  TlsHandshakeFailed,  ///< not TLS 1.3 (a plaintext client, an old TLS version, garbage)
  HandshakeTimeout,    ///< no finished handshake within handshake_timeout_ms
  FrameOversize,       ///< declared length over 64 KiB: Error, then closed
  FrameEmpty,          ///< declared length 0: Error, then closed
  FrameMalformed,      ///< payload not a ClientMessage: Error, then closed
  FrameMissingBody,    ///< a ClientMessage without a body: Error, then closed
  FrameTimeout,        ///< a frame not completed within frame_timeout_ms (slowloris)
  IdleTimeout,         ///< no whole frame within idle_timeout_ms
  WriteTimeout,        ///< a reply not taken by the client within write_timeout_ms
  OutboxFull,          ///< more than max_outbox_bytes of replies waiting for a client
  WrongState,          ///< not allowed in the connection's state: dropped, Error replied
  RateLimited,         ///< over messages_per_second: dropped, Error replied
  InvalidRequest,      ///< a field out of range (chat length ...): Error replied
  // --- accounts (the limits are kept in the database, db/src/login_limits.h) ---
  LoginTimeout,             ///< not logged in within login_timeout_ms of the handshake: closed
  LoginRateLimited,         ///< a login past a failed-login limit: refused before any hashing
  RegistrationRateLimited,  ///< a registration past the address's limit: refused, no hashing
  ServerBusy,  ///< a registration, login or resume refused SERVER_BUSY (a database queue full)
};
inline constexpr std::size_t kControlRefusalCount =
    static_cast<std::size_t>(ControlRefusal::ServerBusy) + 1;

/// Refusals that say an address is (or many are) pushing at the accounts' limits: logged once
/// per episode and address (EpisodeLog), the rest only at debug.
inline bool is_account_refusal(ControlRefusal refusal) {
  return refusal == ControlRefusal::LoginTimeout || refusal == ControlRefusal::LoginRateLimited ||
         refusal == ControlRefusal::RegistrationRateLimited ||
         refusal == ControlRefusal::ServerBusy;
}

inline const char* name(ControlRefusal refusal) {
  switch (refusal) {
    case ControlRefusal::ConnectionCap:
      return "connection_cap";
    case ControlRefusal::AddressCap:
      return "address_cap";
    case ControlRefusal::TlsHandshakeFailed:
      return "tls_handshake_failed";
    case ControlRefusal::HandshakeTimeout:
      return "handshake_timeout";
    case ControlRefusal::FrameOversize:
      return "frame_oversize";
    case ControlRefusal::FrameEmpty:
      return "frame_empty";
    case ControlRefusal::FrameMalformed:
      return "frame_malformed";
    case ControlRefusal::FrameMissingBody:
      return "frame_missing_body";
    case ControlRefusal::FrameTimeout:
      return "frame_timeout";
    case ControlRefusal::IdleTimeout:
      return "idle_timeout";
    case ControlRefusal::WriteTimeout:
      return "write_timeout";
    case ControlRefusal::OutboxFull:
      return "outbox_full";
    case ControlRefusal::WrongState:
      return "wrong_state";
    case ControlRefusal::RateLimited:
      return "rate_limited";
    case ControlRefusal::InvalidRequest:
      return "invalid_request";
    case ControlRefusal::LoginTimeout:
      return "login_timeout";
    case ControlRefusal::LoginRateLimited:
      return "login_rate_limited";
    case ControlRefusal::RegistrationRateLimited:
      return "registration_rate_limited";
    case ControlRefusal::ServerBusy:
      return "server_busy";
  }
  return "unknown";
}

/// A plain copy of the counters at one moment.
struct ControlStats {
  std::uint64_t accepted = 0;     ///< TCP connections accepted (before the caps)
  std::uint64_t handshakes = 0;   ///< TLS handshakes completed
  std::uint64_t closed = 0;       ///< sessions ended, for any reason
  std::uint64_t handshaking = 0;  ///< gauge: sessions in the TLS handshake
  /// gauge: sessions past the handshake, by state (Closed: closing, still flushing)
  std::array<std::uint64_t, proto::kControlStateCount> by_state{};
  std::uint64_t frames_in = 0;
  std::uint64_t frames_out = 0;
  std::uint64_t bytes_in = 0;                                            ///< TLS plaintext bytes
  std::uint64_t bytes_out = 0;                                           ///< TLS plaintext bytes
  std::array<std::uint64_t, proto::kClientMessageKindCount> requests{};  ///< dispatched, by kind
  std::array<std::uint64_t, kControlRefusalCount> refusals{};
};

class ControlCounters {
 public:
  void add(std::atomic<std::uint64_t>& counter, std::uint64_t n = 1) {
    counter.fetch_add(n, std::memory_order_relaxed);
  }
  void refused(ControlRefusal refusal) { add(refusals_[static_cast<std::size_t>(refusal)]); }
  void requested(proto::ClientMessageKind kind) { add(requests_[static_cast<std::size_t>(kind)]); }
  /// Moves one session between the state gauges.
  void enter_state(proto::ControlState state) { add(by_state_[static_cast<std::size_t>(state)]); }
  void leave_state(proto::ControlState state) {
    by_state_[static_cast<std::size_t>(state)].fetch_sub(1, std::memory_order_relaxed);
  }
  std::uint64_t refusals(ControlRefusal refusal) const {
    return refusals_[static_cast<std::size_t>(refusal)].load(std::memory_order_relaxed);
  }

  ControlStats snapshot() const {
    ControlStats stats;
    stats.accepted = accepted.load(std::memory_order_relaxed);
    stats.handshakes = handshakes.load(std::memory_order_relaxed);
    stats.closed = closed.load(std::memory_order_relaxed);
    stats.handshaking = handshaking.load(std::memory_order_relaxed);
    stats.frames_in = frames_in.load(std::memory_order_relaxed);
    stats.frames_out = frames_out.load(std::memory_order_relaxed);
    stats.bytes_in = bytes_in.load(std::memory_order_relaxed);
    stats.bytes_out = bytes_out.load(std::memory_order_relaxed);
    for (std::size_t i = 0; i < stats.by_state.size(); ++i) {
      stats.by_state[i] = by_state_[i].load(std::memory_order_relaxed);
    }
    for (std::size_t i = 0; i < stats.requests.size(); ++i) {
      stats.requests[i] = requests_[i].load(std::memory_order_relaxed);
    }
    for (std::size_t i = 0; i < stats.refusals.size(); ++i) {
      stats.refusals[i] = refusals_[i].load(std::memory_order_relaxed);
    }
    return stats;
  }

  std::atomic<std::uint64_t> accepted{0};
  std::atomic<std::uint64_t> handshakes{0};
  std::atomic<std::uint64_t> closed{0};
  std::atomic<std::uint64_t> handshaking{0};
  std::atomic<std::uint64_t> frames_in{0};
  std::atomic<std::uint64_t> frames_out{0};
  std::atomic<std::uint64_t> bytes_in{0};
  std::atomic<std::uint64_t> bytes_out{0};

 private:
  std::array<std::atomic<std::uint64_t>, proto::kControlStateCount> by_state_{};
  std::array<std::atomic<std::uint64_t>, proto::kClientMessageKindCount> requests_{};
  std::array<std::atomic<std::uint64_t>, kControlRefusalCount> refusals_{};
};

}  // namespace ricochet::server
