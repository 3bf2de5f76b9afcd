// Interpolation of the other entities (interpolator.h): the render time trails the newest
// snapshot by the delay, positions are lerped between the two snapshots around it, never
// extrapolated, and a jump (a respawn) is not smeared across the map.
#include "ricochet/bot/interpolator.h"

#include <gtest/gtest.h>

#include <vector>

namespace ricochet::bot::interpolator_test {
namespace {

std::vector<SeenEntity> one(float x, std::uint32_t id = 7) {
  return {SeenEntity{id, {x, 1, 0}, {6, 0, 0}, 0}};
}

TEST(Interpolator, TheDelayIsTheLargerOf100MsAndTwoSnapshots) {
  EXPECT_DOUBLE_EQ(Interpolator(60, 60).delay_ticks(), 6);   // 100 ms
  EXPECT_DOUBLE_EQ(Interpolator(60, 10).delay_ticks(), 12);  // two 6-tick intervals
}

TEST(Interpolator, ShowsTheStateOneDelayAgoBetweenSnapshots) {
  Interpolator interpolator(60, 30);  // a snapshot every 2 ticks; delay 6 ticks
  for (std::uint32_t tick = 2; tick <= 20; tick += 2) interpolator.add(tick, one(0.1f * tick), 0);
  const RenderTime first = interpolator.advance(0);
  EXPECT_EQ(first.tick, 14u);  // newest 20 - 6
  EXPECT_EQ(first.fraction, 0);
  ASSERT_EQ(interpolator.entities().size(), 1u);
  EXPECT_FLOAT_EQ(interpolator.entities()[0].position_m[0], 1.4f);
  // Half a tick of the bot's clock later (no new snapshot): between tick 14 and 16.
  const RenderTime later = interpolator.advance(0.5 / 60);
  EXPECT_EQ(later.tick, 14u);
  EXPECT_EQ(later.fraction, 128);
  EXPECT_NEAR(interpolator.entities()[0].position_m[0], 1.45f, 1e-5);
}

TEST(Interpolator, NeverExtrapolatesPastTheNewestSnapshot) {
  Interpolator interpolator(60, 60);
  for (std::uint32_t tick = 1; tick <= 10; ++tick) interpolator.add(tick, one(float(tick)), 0);
  interpolator.advance(0);
  // No snapshot for a long stall: the render time stops at the newest.
  RenderTime shown{};
  for (int k = 1; k <= 30; ++k) shown = interpolator.advance(k / 60.0);
  EXPECT_EQ(shown.tick, 10u);
  EXPECT_EQ(shown.fraction, 0);
  EXPECT_FLOAT_EQ(interpolator.entities()[0].position_m[0], 10.0f);
}

TEST(Interpolator, FollowsTheSnapshotsSmoothly) {
  Interpolator interpolator(60, 60);
  double last = 0;
  for (std::uint32_t tick = 1; tick <= 120; ++tick) {
    interpolator.add(tick, one(0.1f * float(tick)), tick / 60.0);
    const RenderTime shown = interpolator.advance(tick / 60.0);
    const double at = shown.tick + shown.fraction / 256.0;
    if (tick > 60) {                              // settled within a second of the first snapshot
      EXPECT_NEAR(at, tick - 6.0, 0.05) << tick;  // the delay holds
      EXPECT_GT(at, last);                        // and time only moves forward
    }
    last = at;
  }
}

TEST(Interpolator, AJumpIsNotLerpedAndNewcomersShowAtOnce) {
  Interpolator interpolator(60, 60);
  interpolator.add(1, one(0), 0);
  std::vector<SeenEntity> second = one(20);  // respawned across the map
  second.push_back(SeenEntity{9, {5, 1, 5}, {}, 0});
  interpolator.add(2, second, 0);
  for (std::uint32_t tick = 3; tick <= 7; ++tick) interpolator.add(tick, second, 0);
  // Render time 7 - 6 = 1, then half a tick on: between the two.
  interpolator.advance(0);
  interpolator.advance(0.5 / 60);
  ASSERT_EQ(interpolator.entities().size(), 2u);
  const float x = interpolator.entities()[0].position_m[0];
  EXPECT_TRUE(x == 0 || x == 20) << x;
  EXPECT_EQ(interpolator.entities()[1].id, 9u);
}

TEST(Interpolator, IgnoresOlderSnapshots) {
  Interpolator interpolator(60, 60);
  interpolator.add(5, one(5), 0);
  interpolator.add(3, one(3), 0);
  interpolator.advance(0);
  EXPECT_FLOAT_EQ(interpolator.entities()[0].position_m[0], 5.0f);
}

}  // namespace
}  // namespace ricochet::bot::interpolator_test
