#pragma once
/// The fixed tick of a match: an accumulator on a steady time the caller passes in (the match
/// never reads a clock). Each call to advance(now) says how many fixed steps are due; when the
/// process fell so far behind that more than max_catch_up_steps are due, it runs the cap and
/// drops the rest (no spiral of death), counting an overrun.
///
/// The step boundaries are exact in integer microseconds times the rate, so 60 Hz does not drift
/// although 1/60 s is not a whole number of microseconds.

#include <cstdint>
#include <string>

#include "ricochet/proto/clock.h"

namespace ricochet::server {

struct TickClockConfig {
  int rate_hz = 60;            ///< fixed steps per second, 10..128
  int max_catch_up_steps = 5;  ///< most steps one advance() returns, 1..64

  /// Empty when valid; otherwise names the field, the allowed range and what came.
  std::string validate() const;
};

class TickClock {
 public:
  /// `config` must be valid (validate() empty). The first step is due one period after `start`.
  TickClock(const TickClockConfig& config, proto::TimeUs start);

  /// How many fixed steps to run now, 0..max_catch_up_steps. A time earlier than the last one
  /// (a clock that went back) runs nothing.
  int advance(proto::TimeUs now);

  /// s, the fixed step's duration.
  double step_s() const { return 1.0 / config_.rate_hz; }
  int rate_hz() const { return config_.rate_hz; }
  /// Time at which the next step is due: sleep until then.
  proto::TimeUs next_step_at() const;

  std::uint64_t steps() const { return steps_; }            ///< steps returned so far
  std::uint64_t late_calls() const { return late_calls_; }  ///< advance() calls that ran > 1 step
  std::uint64_t overruns() const { return overruns_; }      ///< calls that hit the catch-up cap
  std::uint64_t dropped_steps() const { return dropped_steps_; }  ///< steps never run

 private:
  TickClockConfig config_;
  proto::TimeUs origin_;                 ///< µs; steps are due at origin + k / rate
  std::int64_t steps_since_origin_ = 0;  ///< k of the last step returned
  std::uint64_t steps_ = 0;
  std::uint64_t late_calls_ = 0;
  std::uint64_t overruns_ = 0;
  std::uint64_t dropped_steps_ = 0;
};

}  // namespace ricochet::server
