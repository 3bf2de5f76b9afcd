#pragma once
/// The one clock the server's game side runs on: the steady clock in µs. Matches, the game
/// channel and connect tokens all read it here, so a token's expiry and the transport's timeouts
/// are on the same clock (proto/clock.h).

#include <chrono>

#include "ricochet/proto/clock.h"

namespace ricochet::server {

inline proto::TimeUs steady_now_us() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

inline std::chrono::steady_clock::time_point steady_time_point(proto::TimeUs at) {
  return std::chrono::steady_clock::time_point(std::chrono::microseconds(at));
}

}  // namespace ricochet::server
