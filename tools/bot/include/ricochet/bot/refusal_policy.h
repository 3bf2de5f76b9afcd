#pragma once
/// What a bot does when the control channel refuses its sign-in or its join, and how long it
/// waits before trying again. Sans-IO: the random draw is a parameter.
///
///   SERVER_BUSY (a password queue full)      -> Retry: back-off, not a failed attempt; the
///                                               server answered, it is only busy
///   MATCH_FULL, ADDRESS_SEAT_LIMIT           -> WaitForRoom: list again shortly, not a failed
///                                               attempt (seats free as players leave)
///   LOGIN_RATE_LIMITED, anything else        -> FailedAttempt (max_reconnect_attempts)

#include <cstdint>

#include "ricochet/wire/control.pb.h"

namespace ricochet::bot {

enum class RefusalAction : std::uint8_t {
  Retry,          ///< the same request after busy_backoff_s(); failed attempts stay as they are
  WaitForRoom,    ///< look for a match again after a second; failed attempts stay as they are
  FailedAttempt,  ///< counted towards giving up
};

RefusalAction refusal_action(wire::ErrorCode code);

/// Seconds before busy retry `attempt` (1, 2, ...): 0.5 s doubling up to 8 s, times a factor in
/// [0.5, 1.5) from `unit` (uniform in [0, 1)), so that bots refused together do not all come
/// back together.
double busy_backoff_s(int attempt, double unit);

}  // namespace ricochet::bot
