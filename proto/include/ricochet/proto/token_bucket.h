#pragma once
/// A rate limit as a token bucket: up to `burst` events at once, refilled at `per_second`
/// events per second. Time is a parameter (µs, proto/clock.h); the bucket never reads a clock.
/// The game server budgets packets per address and per client with it, the control channel
/// requests per connection.

#include <algorithm>

#include "ricochet/proto/clock.h"

namespace ricochet::proto {

class TokenBucket {
 public:
  /// Starts full: `burst` tokens at `now`. `per_second` > 0, `burst` >= 1.
  TokenBucket(double per_second, double burst, TimeUs now)
      : per_second_(per_second), burst_(burst), tokens_(burst), updated_(now) {}

  /// Takes one token; false when the budget is exhausted (then nothing is taken). A `now`
  /// earlier than the last call's refills nothing.
  bool take(TimeUs now) {
    refill(now);
    if (tokens_ < 1.0) return false;
    tokens_ -= 1.0;
    return true;
  }
  /// True when take() would succeed now; takes nothing.
  bool available(TimeUs now) {
    refill(now);
    return tokens_ >= 1.0;
  }
  /// True when refilled to the burst: the bucket holds no more state than a fresh one.
  bool full(TimeUs now) {
    refill(now);
    return tokens_ >= burst_;
  }

 private:
  void refill(TimeUs now) {
    if (now > updated_) {
      tokens_ = std::min(burst_, tokens_ + per_second_ * static_cast<double>(now - updated_) /
                                               static_cast<double>(kMicrosPerSecond));
      updated_ = now;
    }
  }
  double per_second_;
  double burst_;
  double tokens_;
  TimeUs updated_;
};

}  // namespace ricochet::proto
