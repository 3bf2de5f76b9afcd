// The fixed tick's accumulator, driven by fake time.

#include "ricochet/server/tick_clock.h"

#include <gtest/gtest.h>

namespace ricochet::server::tick_clock_test {
namespace {

using proto::kMicrosPerSecond;
using proto::TimeUs;

TEST(TickClockConfig, ValidatesTheRateAndTheCap) {
  EXPECT_EQ(TickClockConfig{}.validate(), "");
  EXPECT_EQ((TickClockConfig{9, 5}).validate(), "tick rate_hz must be 10..128, got 9");
  EXPECT_EQ((TickClockConfig{129, 5}).validate(), "tick rate_hz must be 10..128, got 129");
  EXPECT_EQ((TickClockConfig{60, 0}).validate(), "tick max_catch_up_steps must be 1..64, got 0");
  EXPECT_EQ((TickClockConfig{10, 64}).validate(), "");
  EXPECT_EQ((TickClockConfig{128, 1}).validate(), "");
}

TEST(TickClock, RunsOneStepPerPeriod) {
  const TimeUs start = 5'000'000;
  TickClock clock({60, 5}, start);
  EXPECT_EQ(clock.advance(start), 0);
  EXPECT_EQ(clock.advance(start + 16'666), 0);  // 1/60 s is 16666.67 µs
  EXPECT_EQ(clock.advance(start + 16'667), 1);
  EXPECT_EQ(clock.advance(start + 16'667), 0);
  EXPECT_EQ(clock.next_step_at(), start + 33'334);
  EXPECT_EQ(clock.advance(start + 33'333), 0);
  EXPECT_EQ(clock.advance(start + 33'334), 1);
  EXPECT_DOUBLE_EQ(clock.step_s(), 1.0 / 60);
}

TEST(TickClock, DoesNotDriftOverAMinuteAtSixtyHertz) {
  TickClock clock({60, 5}, 0);
  int steps = 0;
  // Polled every millisecond for a minute: exactly 3600 steps, never two at once.
  for (TimeUs now = 1'000; now <= 60 * kMicrosPerSecond; now += 1'000) {
    const int due = clock.advance(now);
    EXPECT_LE(due, 1);
    steps += due;
  }
  EXPECT_EQ(steps, 3600);
  EXPECT_EQ(clock.steps(), 3600u);
  EXPECT_EQ(clock.late_calls(), 0u);
  EXPECT_EQ(clock.overruns(), 0u);
}

TEST(TickClock, SleepingUntilTheNextStepRunsEveryStep) {
  TickClock clock({128, 5}, 1'000);
  for (int k = 0; k < 1000; ++k) {
    const TimeUs at = clock.next_step_at();
    EXPECT_EQ(clock.advance(at - 1), 0);
    EXPECT_EQ(clock.advance(at), 1);
  }
  EXPECT_EQ(clock.steps(), 1000u);
}

TEST(TickClock, CatchesUpWithinTheCap) {
  TickClock clock({60, 5}, 0);
  // 3 periods late: runs 3, counted as late but not an overrun.
  EXPECT_EQ(clock.advance(50'001), 3);
  EXPECT_EQ(clock.late_calls(), 1u);
  EXPECT_EQ(clock.overruns(), 0u);
  EXPECT_EQ(clock.dropped_steps(), 0u);
}

TEST(TickClock, DropsWhatIsBeyondTheCapAndCountsAnOverrun) {
  TickClock clock({60, 4}, 0);
  // A one-second stall: 60 due, 4 run, 56 dropped; then back on a 60 Hz rhythm from there.
  EXPECT_EQ(clock.advance(kMicrosPerSecond), 4);
  EXPECT_EQ(clock.overruns(), 1u);
  EXPECT_EQ(clock.dropped_steps(), 56u);
  EXPECT_EQ(clock.advance(kMicrosPerSecond + 16'666), 0);
  EXPECT_EQ(clock.advance(kMicrosPerSecond + 16'667), 1);
  EXPECT_EQ(clock.next_step_at(), kMicrosPerSecond + 33'334);
  EXPECT_EQ(clock.steps(), 5u);
}

TEST(TickClock, ATimeGoingBackRunsNothing) {
  TickClock clock({20, 5}, 1'000'000);
  EXPECT_EQ(clock.advance(1'100'000), 2);
  EXPECT_EQ(clock.advance(900'000), 0);
  EXPECT_EQ(clock.advance(1'100'000), 0);
  EXPECT_EQ(clock.advance(1'150'000), 1);
}

}  // namespace
}  // namespace ricochet::server::tick_clock_test
