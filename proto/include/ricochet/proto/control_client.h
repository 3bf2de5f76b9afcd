#pragma once
/// The client end of the control channel as a sans-IO state machine (PROTOCOL.md Control
/// channel, The client end): the server's bytes and the time in; frames to write, replies and
/// server messages out. It numbers requests, matches every reply to its request, follows the
/// connection's states (control_states.h) and refuses locally what the state does not allow,
/// times requests out, sends keep-alive pings, and checks the server's bytes like any untrusted
/// input. The TLS connection and its certificate pinning are the caller's: one ControlClient per
/// TLS connection, made once TLS is up. No sockets, no threads, no clock. Not thread-safe.
///
///   Unauthenticated ──SessionReply──▶ Authenticated ──JoinMatchReply──▶ InMatch
///         │                             ▲ ◀──LeaveMatchReply / NOT_IN_MATCH / MatchResults──┘
///         └──SessionReply with match_id, answering a resume (back in the match)──────▶ InMatch
///   any state ──close(), connection_lost(), the server's closing Error, a request timeout,
///               a refused server frame──▶ Closed (final: ControlClosed says why)

#include <array>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "ricochet/proto/clock.h"
#include "ricochet/proto/control_states.h"
#include "ricochet/proto/frame.h"
#include "ricochet/wire/control.pb.h"

namespace ricochet::proto {

struct ControlClientConfig {
  /// A request with no reply this long after it was queued closes the client (its late reply
  /// could match nothing); 0: requests never time out. A login waits behind every other
  /// password hash the server is doing, hence a minute.
  TimeUs request_timeout_us = 60 * kMicrosPerSecond;
  /// A Ping is queued when nothing was sent for this long, so the server's idle timeout (120 s)
  /// never closes a quiet connection; its Pong is consumed here. 0: no keep-alive pings.
  TimeUs keep_alive_us = 30 * kMicrosPerSecond;
  /// Called once per state change with its reason (for the caller's log); may be empty.
  ControlStateMachine::Observer on_transition;
};

/// Why a request was refused locally; a refused request is never sent.
enum class RequestRefusal : std::uint8_t {
  WrongState,  ///< the state table (control_states.h) does not allow its kind in this state
  Closed,      ///< the client is closed
  NoBody,      ///< the message has no body set
  TooLarge,    ///< it serialises to more than kMaxFramePayloadBytes
};
inline constexpr std::size_t kRequestRefusalCount =
    static_cast<std::size_t>(RequestRefusal::TooLarge) + 1;
const char* name(RequestRefusal refusal);

/// Why the client closed. From FrameOversize on, the server sent something the protocol does not
/// allow and the client refused it.
enum class ControlCloseReason : std::uint8_t {
  Requested,          ///< close() by the caller
  ConnectionLost,     ///< the caller saw the stream end or fail (connection_lost())
  ServerError,        ///< the server's Error with request_id 0, its last word before it closes
  RequestTimeout,     ///< a request had no reply within request_timeout_us
  FrameOversize,      ///< a frame header declared over kMaxFramePayloadBytes
  FrameEmpty,         ///< a frame header declared 0 bytes
  Malformed,          ///< a payload that is not a ServerMessage
  MissingBody,        ///< a ServerMessage with no body
  UnknownRequest,     ///< a reply to a request id that is not pending
  WrongReply,         ///< a reply whose body does not answer its request's kind
  UnexpectedMessage,  ///< request_id 0 with a body other than MatchResults or Error
};
inline constexpr std::size_t kControlCloseReasonCount =
    static_cast<std::size_t>(ControlCloseReason::UnexpectedMessage) + 1;
const char* name(ControlCloseReason reason);
/// True for the reasons that refuse the server's input.
constexpr bool refuses_server(ControlCloseReason reason) {
  return reason >= ControlCloseReason::FrameOversize;
}

/// The answer to a request: its reply body, or an Error (the request was not done; the
/// connection stays open unless a ControlClosed follows).
struct ControlReply {
  std::uint32_t request_id = 0;
  ClientMessageKind kind = ClientMessageKind::Ping;  ///< the request's
  wire::ServerMessage message;                       ///< request_id == request_id

  const wire::Error* error() const { return message.has_error() ? &message.error() : nullptr; }
};
/// A match this account played ended (sent by the server unasked).
struct ControlMatchResults {
  wire::MatchResults results;
};
/// The client is Closed; requests still pending get no reply.
struct ControlClosed {
  ControlCloseReason reason = ControlCloseReason::Requested;
  std::string detail;        ///< for people: what came and what was expected
  wire::Error server_error;  ///< ServerError: what the server said
};
using ControlEvent = std::variant<ControlReply, ControlMatchResults, ControlClosed>;

struct ControlClientCounters {
  std::uint64_t frames_in = 0;
  std::uint64_t frames_out = 0;
  std::uint64_t bytes_in = 0;
  std::uint64_t bytes_out = 0;
  std::uint64_t keep_alives = 0;  ///< pings this client sent on its own
  std::array<std::uint64_t, kRequestRefusalCount> refused_requests{};  ///< by RequestRefusal
  std::array<std::uint64_t, kControlCloseReasonCount> closes{};  ///< by ControlCloseReason, ≤ 1
};

/// A request's number, or why it was refused locally.
struct RequestResult {
  std::uint32_t request_id = 0;  ///< 1..2^32-1 when queued; 0 when refused
  std::optional<RequestRefusal> refusal;

  explicit operator bool() const { return !refusal; }
};

class ControlClient {
 public:
  explicit ControlClient(TimeUs now, ControlClientConfig config = {});

  /// Queues `message` (one of the requests, its body set) with the next request id
  /// (numbered from 1, wrapping past 2^32-1 to 1; any request_id in it is replaced), unless the
  /// current state does not allow its kind. A request is checked against the state as it is,
  /// not as pending requests may leave it: send list_matches after the login's reply, not with
  /// it. Replies are matched by request id, in whatever order they come.
  RequestResult request(wire::ClientMessage message, TimeUs now);
  /// Bytes received from the server, split anywhere. Each whole frame is handled at once: its
  /// reply or MatchResults becomes an event, or it closes the client with the reason it was
  /// refused.
  void receive(std::span<const std::uint8_t> bytes);
  /// Request timeouts and keep-alive pings; call it at deadline() (earlier is harmless).
  void update(TimeUs now);
  /// When update() has something to do next; nullopt when nothing is pending (or Closed).
  std::optional<TimeUs> deadline() const;

  /// Moves every frame queued since the last call into `out` (its content is replaced, its
  /// buffer reused); false when nothing is queued. Nothing is queued once Closed.
  bool poll_transmit(std::vector<std::uint8_t>& out);
  bool poll_event(ControlEvent& out);

  /// The stream ended or failed (`why`, for people); no-op once Closed.
  void connection_lost(std::string_view why);
  /// The caller is done: drops what is queued and pending. No-op once Closed.
  void close();

  ControlState state() const { return machine_.state(); }
  bool admits(ClientMessageKind kind) const { return machine_.admits(kind); }
  /// Requests sent and not answered yet, keep-alive pings included.
  std::size_t pending() const { return pending_.size(); }
  const ControlClientCounters& counters() const { return counters_; }

 private:
  struct Pending {
    std::uint32_t request_id = 0;
    ClientMessageKind kind = ClientMessageKind::Ping;
    TimeUs sent_at = 0;
    bool keep_alive = false;  ///< this client's own ping: its Pong is no event
  };

  std::uint32_t queue(wire::ClientMessage& message, ClientMessageKind kind, TimeUs now);
  void on_message(const wire::ServerMessage& message);
  void on_reply(const wire::ServerMessage& message);
  void end(ControlCloseReason reason, std::string detail, wire::Error server_error = {});

  ControlClientConfig config_;
  ControlStateMachine machine_;
  FrameReader reader_;
  std::vector<std::uint8_t> payload_;  ///< the frame being handled
  std::vector<std::uint8_t> outbox_;   ///< frames queued for poll_transmit
  std::deque<Pending> pending_;        ///< in the order sent
  std::deque<ControlEvent> events_;
  std::uint32_t last_request_id_ = 0;
  TimeUs last_sent_ = 0;  ///< when a frame was last queued (keep-alive)
  ControlClientCounters counters_;
};

}  // namespace ricochet::proto
