#pragma once
/// The one clock the server runs on: the steady clock in µs. Matches and the game channel read
/// it here; the match registry (seats, connect tokens), the control channel (deadlines, message
/// rate) and the admin port (request deadlines) are given it as a clock function in their
/// configs, which tests replace with fake time. A token's expiry and the transport's timeouts
/// are so on the same clock (proto/clock.h).

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
