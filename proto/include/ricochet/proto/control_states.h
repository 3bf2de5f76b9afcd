#pragma once
/// The control connection's states and the one table of which client messages each allows,
/// sans-IO. The server session asks admits() before it dispatches anything and moves between
/// states only through ControlStateMachine::transition(), which reports each change once with
/// its reason.
///
///   Unauthenticated ──login / resume──▶ Authenticated ──join──▶ InMatch
///        ▲                               ▲   ◀──leave / match results──┘
///        └──────────── logout ◀──────────┴──────────────────────────┘
///   Unauthenticated ──resume, the sign-in's seat still held (back in the match)──▶ InMatch
///   any state ──close(reason)──▶ Closed (final)
///
///   message        Unauthenticated  Authenticated  InMatch  Closed
///   register             yes             -            -        -
///   login                yes             -            -        -
///   resume               yes             -            -        -
///   list_matches          -             yes          yes       -
///   create_match          -             yes          yes       -
///   join_match            -             yes          yes       -     (in a match: same match
///   leave_match           -              -           yes       -      re-issues the token)
///   chat                  -              -           yes       -
///   ping                 yes            yes          yes       -
///   logout                -             yes          yes       -
///   find_match            -             yes          yes       -

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string_view>
#include <utility>

#include "ricochet/wire/control.pb.h"

namespace ricochet::proto {

enum class ControlState : std::uint8_t { Unauthenticated, Authenticated, InMatch, Closed };
inline constexpr std::size_t kControlStateCount =
    static_cast<std::size_t>(ControlState::Closed) + 1;

inline const char* name(ControlState state) {
  switch (state) {
    case ControlState::Unauthenticated:
      return "unauthenticated";
    case ControlState::Authenticated:
      return "authenticated";
    case ControlState::InMatch:
      return "in_match";
    case ControlState::Closed:
      return "closed";
  }
  return "unknown";
}

/// The client message kinds, in the order of ClientMessage's oneof.
enum class ClientMessageKind : std::uint8_t {
  Register,
  Login,
  Resume,
  ListMatches,
  CreateMatch,
  JoinMatch,
  LeaveMatch,
  Chat,
  Ping,
  Logout,
  FindMatch,
};
inline constexpr std::size_t kClientMessageKindCount =
    static_cast<std::size_t>(ClientMessageKind::FindMatch) + 1;

inline const char* name(ClientMessageKind kind) {
  switch (kind) {
    case ClientMessageKind::Register:
      return "register";
    case ClientMessageKind::Login:
      return "login";
    case ClientMessageKind::Resume:
      return "resume";
    case ClientMessageKind::ListMatches:
      return "list_matches";
    case ClientMessageKind::CreateMatch:
      return "create_match";
    case ClientMessageKind::JoinMatch:
      return "join_match";
    case ClientMessageKind::LeaveMatch:
      return "leave_match";
    case ClientMessageKind::Chat:
      return "chat";
    case ClientMessageKind::Ping:
      return "ping";
    case ClientMessageKind::Logout:
      return "logout";
    case ClientMessageKind::FindMatch:
      return "find_match";
  }
  return "unknown";
}

/// The kind of a parsed message that has a body (parse_client_message() guarantees one).
inline ClientMessageKind kind_of(const wire::ClientMessage& message) {
  switch (message.body_case()) {
    case wire::ClientMessage::kRegisterAccount:
      return ClientMessageKind::Register;
    case wire::ClientMessage::kLogin:
      return ClientMessageKind::Login;
    case wire::ClientMessage::kResume:
      return ClientMessageKind::Resume;
    case wire::ClientMessage::kListMatches:
      return ClientMessageKind::ListMatches;
    case wire::ClientMessage::kCreateMatch:
      return ClientMessageKind::CreateMatch;
    case wire::ClientMessage::kJoinMatch:
      return ClientMessageKind::JoinMatch;
    case wire::ClientMessage::kLeaveMatch:
      return ClientMessageKind::LeaveMatch;
    case wire::ClientMessage::kChat:
      return ClientMessageKind::Chat;
    case wire::ClientMessage::kPing:
      return ClientMessageKind::Ping;
    case wire::ClientMessage::kLogout:
      return ClientMessageKind::Logout;
    case wire::ClientMessage::kFindMatch:
      return ClientMessageKind::FindMatch;
    case wire::ClientMessage::BODY_NOT_SET:
      break;
  }
  return ClientMessageKind::Ping;
}

// clang-format off
/// kAllowed[state][kind]: whether a message of that kind is dispatched in that state.
inline constexpr std::array<std::array<bool, kClientMessageKindCount>, kControlStateCount>
    kAllowedMessages{{
        // register login resume list  create join  leave  chat   ping   logout find
        {{true, true, true, false, false, false, false, false, true, false, false}},  // Unauthenticated
        {{false, false, false, true, true, true, false, false, true, true, true}},    // Authenticated
        {{false, false, false, true, true, true, true, true, true, true, true}},      // InMatch
        {{false, false, false, false, false, false, false, false, false, false, false}},  // Closed
    }};
// clang-format on

inline constexpr bool admits(ControlState state, ClientMessageKind kind) {
  return kAllowedMessages[static_cast<std::size_t>(state)][static_cast<std::size_t>(kind)];
}

/// The state of one connection. Every change goes through transition(), which calls the
/// observer once (from, to, reason); Closed is final.
class ControlStateMachine {
 public:
  using Observer = std::function<void(ControlState from, ControlState to, std::string_view reason)>;

  explicit ControlStateMachine(Observer observer = {}) : observer_(std::move(observer)) {}

  ControlState state() const { return state_; }
  bool admits(ClientMessageKind kind) const { return proto::admits(state_, kind); }

  /// Moves to `to` with `reason`; returns false (and changes nothing) when already there or
  /// when the connection is Closed.
  bool transition(ControlState to, std::string_view reason) {
    if (state_ == to || state_ == ControlState::Closed) return false;
    const ControlState from = state_;
    state_ = to;
    if (observer_) observer_(from, to, reason);
    return true;
  }

 private:
  ControlState state_ = ControlState::Unauthenticated;
  Observer observer_;
};

}  // namespace ricochet::proto
