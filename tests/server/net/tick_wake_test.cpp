// When a match's host wakes for a tick: on a shared grid, never before the tick is due.

#include "tick_wake.h"

#include <gtest/gtest.h>

#include <set>

namespace ricochet::server::tick_wake_test {
namespace {

using proto::TimeUs;

TEST(TickWake, TheGrainIsOneMillisecondOrAnEighthOfAFastTick) {
  EXPECT_EQ(tick_wake_grain_us(10), 1000);
  EXPECT_EQ(tick_wake_grain_us(60), 1000);
  EXPECT_EQ(tick_wake_grain_us(125), 1000);
  EXPECT_EQ(tick_wake_grain_us(128), 976);  // 7812 µs / 8
}

TEST(TickWake, WakesAtTheFirstGridPointAtOrAfterTheTickIsDue) {
  EXPECT_EQ(tick_wake_at(5'000'000, 60), 5'000'000);  // due on the grid: no later
  EXPECT_EQ(tick_wake_at(5'000'001, 60), 5'001'000);
  EXPECT_EQ(tick_wake_at(5'000'999, 60), 5'001'000);
  EXPECT_EQ(tick_wake_at(0, 60), 0);
  EXPECT_EQ(tick_wake_at(1'953, 128), 2'928);  // 2 · 976 = 1952 < 1953 <= 3 · 976
}

TEST(TickWake, NeverEarlierAndAtMostOneGrainLate) {
  for (const int rate : {10, 30, 60, 100, 128}) {
    const TimeUs grain = tick_wake_grain_us(rate);
    for (TimeUs due = 1'234'567; due < 1'234'567 + 3 * grain; due += 7) {
      const TimeUs wake = tick_wake_at(due, rate);
      ASSERT_GE(wake, due) << rate << " Hz, due " << due;
      ASSERT_LT(wake - due, grain) << rate << " Hz, due " << due;
      ASSERT_EQ(wake % grain, 0) << rate << " Hz, due " << due;
    }
  }
}

TEST(TickWake, MatchesDueWithinOneGrainShareOneWake) {
  // 94 matches at 60 Hz whose ticks fall due spread evenly over one period: on the grid they
  // need 17 or 18 distinct wake times (the grid points a 16.7 ms span holds), not 94.
  std::set<TimeUs> wakes;
  const TimeUs period = 16'667;
  for (int match = 0; match < 94; ++match) {
    wakes.insert(tick_wake_at(10'000'000 + match * period / 94, 60));
  }
  EXPECT_LE(wakes.size(), 18u);
  EXPECT_GE(wakes.size(), 16u);
}

}  // namespace
}  // namespace ricochet::server::tick_wake_test
