#pragma once
/// A packet budget: `burst` packets at once, refilled at `per_second`. Time in microseconds.

#include <algorithm>

#include "ricochet/proto/clock.h"

namespace ricochet::proto {

class TokenBucket {
 public:
  TokenBucket(double per_second, double burst, TimeUs now)
      : per_second_(per_second), burst_(burst), tokens_(burst), updated_(now) {}

  /// Takes one token; false when the budget is exhausted.
  bool take(TimeUs now) {
    refill(now);
    if (tokens_ < 1.0) return false;
    tokens_ -= 1.0;
    return true;
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
