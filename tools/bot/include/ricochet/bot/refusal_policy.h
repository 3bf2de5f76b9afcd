#pragma once
/// What a bot does when the control channel refuses its sign-in or its join, and how long it
/// waits before trying again. Sans-IO: the random draw is a parameter.
///
///   SERVER_BUSY (a password queue full)      -> Retry: back-off, not a failed attempt; the
///                                               server answered, it is only busy
///   MATCH_FULL, ADDRESS_SEAT_LIMIT           -> WaitForRoom: list again shortly, not a failed
///                                               attempt (seats free as players leave)
///   LOGIN_RATE_LIMITED, anything else        -> FailedAttempt (max_reconnect_attempts)
///
/// Placement (--find-match; PROTOCOL.md, Placement), a find_match or a join with its ticket:
///
///   MATCH_FULL, UNKNOWN_TICKET, EXPIRED_TICKET, -> FindAgain: the ticket is spent or its seat
///   MATCH_NOT_FOUND, ADDRESS_SEAT_LIMIT            gone (the directory's view of the seats
///                                                  was old); find_match again after
///                                                  find_again_s(), at most
///                                                  kMaxFindAgainInARow times in a row
///   NO_SERVER_AVAILABLE, FIND_MATCH_RATE_LIMITED -> RetryLater: the same find_match after
///   SERVER_BUSY                                    retry_later_s(); the fleet is full or busy,
///                                                  not wrong (no limit: seats free as matches end)
///   UNKNOWN_MODE_OR_MAP, INVALID_REQUEST         -> GiveUp: no server will ever host what was
///                                                  asked; the bot ends with the reason
///   anything else                                -> FailedAttempt

#include <cstdint>

#include "ricochet/wire/control.pb.h"

namespace ricochet::bot {

enum class RefusalAction : std::uint8_t {
  Retry,          ///< the same request after busy_backoff_s(); failed attempts stay as they are
  WaitForRoom,    ///< look for a match again after a second; failed attempts stay as they are
  FailedAttempt,  ///< counted towards giving up
};

RefusalAction refusal_action(wire::ErrorCode code);

enum class PlacementAction : std::uint8_t {
  FindAgain,      ///< a new find_match after find_again_s(refusals in a row), bounded
  RetryLater,     ///< the same find_match after retry_later_s(); unbounded
  GiveUp,         ///< what was asked cannot be placed: end the bot
  FailedAttempt,  ///< counted towards giving up (max_reconnect_attempts)
};

PlacementAction placement_action(wire::ErrorCode code);

/// Tickets refused (FindAgain) in a row before the bot gives up: the fleet keeps handing out
/// seats it cannot seat, which retrying will not mend.
inline constexpr int kMaxFindAgainInARow = 10;

/// Seconds before find_match again after refusal `attempt` (1, 2, ...) in a row: 0.25 s doubling
/// up to 2 s, times a factor in [0.5, 1.5) from `unit`. The cap is about one directory heartbeat
/// (2 s by default): the seats the directory shows are new after each, so waiting longer finds
/// nothing the next heartbeat would not show.
double find_again_s(int attempt, double unit);

/// Seconds before a find_match refused RetryLater is sent again: 2 s (find_match's rate once its
/// burst is spent: 30 a minute) times a factor in [0.5, 1.5) from `unit` (uniform in [0, 1)).
double retry_later_s(double unit);

/// Seconds before busy retry `attempt` (1, 2, ...): 0.5 s doubling up to 8 s, times a factor in
/// [0.5, 1.5) from `unit` (uniform in [0, 1)), so that bots refused together do not all come
/// back together.
double busy_backoff_s(int attempt, double unit);

}  // namespace ricochet::bot
