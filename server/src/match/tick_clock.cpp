/// The fixed-step accumulator (tick_clock.h).

#include "ricochet/server/tick_clock.h"

namespace ricochet::server {

std::string TickClockConfig::validate() const {
  if (rate_hz < 10 || rate_hz > 128) {
    return "tick rate_hz must be 10..128, got " + std::to_string(rate_hz);
  }
  if (max_catch_up_steps < 1 || max_catch_up_steps > 64) {
    return "tick max_catch_up_steps must be 1..64, got " + std::to_string(max_catch_up_steps);
  }
  return {};
}

TickClock::TickClock(const TickClockConfig& config, proto::TimeUs start)
    : config_(config), origin_(start) {}

int TickClock::advance(proto::TimeUs now) {
  if (now <= origin_) return 0;
  // Whole periods elapsed since the origin: (now - origin) * rate / 1e6, exact in integers.
  const std::int64_t elapsed_steps = (now - origin_) * config_.rate_hz / proto::kMicrosPerSecond;
  std::int64_t due = elapsed_steps - steps_since_origin_;
  if (due <= 0) return 0;
  if (due > config_.max_catch_up_steps) {
    ++overruns_;
    dropped_steps_ += static_cast<std::uint64_t>(due - config_.max_catch_up_steps);
    due = config_.max_catch_up_steps;
    // Re-phase on now: the dropped steps are forgotten, the next is due one period later.
    origin_ = now;
    steps_since_origin_ = 0;
  } else {
    steps_since_origin_ = elapsed_steps;
  }
  if (due > 1) ++late_calls_;
  steps_ += static_cast<std::uint64_t>(due);
  return static_cast<int>(due);
}

proto::TimeUs TickClock::next_step_at() const {
  // The smallest t with (t - origin) * rate / 1e6 >= k + 1, i.e. ceil((k + 1) * 1e6 / rate).
  const std::int64_t k = steps_since_origin_ + 1;
  return origin_ + (k * proto::kMicrosPerSecond + config_.rate_hz - 1) / config_.rate_hz;
}

}  // namespace ricochet::server
