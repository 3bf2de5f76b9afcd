// Lag compensation over a real physics world with fake ticks: a target walks along +X at
// 6 m/s (0.1 m per 60 Hz tick), the shooter fires along -Z from z = 10.

#include "ricochet/server/lag_compensation.h"

#include <gtest/gtest.h>

#include <vector>

#include "ricochet/physics/scene_profile.h"
#include "ricochet/server/movement.h"

namespace ricochet::server::lag_compensation_test {
namespace {

using physics::Real;
using physics::Vec3;

constexpr int kRate = 60;
constexpr std::uint32_t kShooter = 1;
constexpr std::uint32_t kTarget = 2;
constexpr float kRadius = 0.4f;
constexpr std::uint32_t kNow = 60;
constexpr Real kEps = Real(1e-4);

/// Target x (m) at `tick`: 0.1 m per tick.
Real walked_x(std::uint32_t tick) {
  return Real(0.1) * Real(tick);
}

class LagCompensationTest : public testing::Test {
 protected:
  LagCompensationTest()
      : world_(physics::World::create(physics::profiles::arena_players()).value()) {
    shooter_body_ = world_.create_body(player_body_def(Vec3(0, 1, 10))).value();
    target_body_ = world_.create_body(player_body_def(Vec3(walked_x(kNow), 1, 0))).value();
  }

  LagSample sample(std::uint32_t entity, const Vec3& position, std::uint32_t life = 0) const {
    LagSample s;
    s.entity_id = entity;
    s.body = entity == kShooter ? shooter_body_ : target_body_;
    s.position_m = position;
    s.radius_m = kRadius;
    s.life = life;
    s.hittable = true;
    return s;
  }

  /// Ticks first..last: the shooter stands at (0, 1, 10), the target walks.
  void record_walk(LagCompensation& lag, std::uint32_t first, std::uint32_t last) const {
    for (std::uint32_t tick = first; tick <= last; ++tick) {
      const LagSample players[] = {sample(kShooter, Vec3(0, 1, 10)),
                                   sample(kTarget, Vec3(walked_x(tick), 1, 0))};
      lag.record(tick, players);
    }
  }

  /// A shot along -Z at height 1 from (x, 1, 10), from the shooter.
  bool shoot(const LagCompensation& lag, const ViewTime& view, Real x, physics::RayHit& hit) const {
    return lag.cast(world_, Vec3(x, 1, 10), Vec3(0, 0, -1), 50, view, kShooter, hit);
  }

  /// The rewound centre of the target at `view`.
  Vec3 target_at(const LagCompensation& lag, const ViewTime& view) const {
    std::vector<physics::SphereProxy> spheres;
    lag.rewound_targets(view, kShooter, spheres);
    EXPECT_EQ(spheres.size(), 1u);
    return spheres.empty() ? Vec3::Constant(-1000) : spheres[0].center;
  }

  physics::World world_;
  physics::BodyId shooter_body_;
  physics::BodyId target_body_;
  LagCompensationConfig config_;
};

TEST_F(LagCompensationTest, ShotWhereTheTargetWas100MsEarlierHitsOnlyWithCompensation) {
  LagCompensation lag(config_, kRate);
  record_walk(lag, 1, kNow);
  // 66.7 ms one way + 33.3 ms interpolation: the client showed tick 54, 100 ms ago.
  const ViewTime view = lag.resolve(kNow, kNow - 6, 0, 66.7);
  EXPECT_EQ(view.tick, kNow - 6);
  EXPECT_EQ(view.fraction, 0.0f);
  EXPECT_NEAR(view.rewind_ms, 100.0, 1e-6);
  EXPECT_FALSE(view.clamped);

  const std::uint64_t hash = world_.state_hash();
  physics::RayHit hit;
  ASSERT_TRUE(shoot(lag, view, walked_x(kNow - 6), hit));
  EXPECT_EQ(hit.target.user_data, kTarget);
  EXPECT_EQ(hit.target.body, target_body_);
  EXPECT_NEAR(hit.distance, 10 - kRadius, kEps);
  // The live body stands at x = 6.0 and is not tested, nor moved.
  EXPECT_FALSE(shoot(lag, view, walked_x(kNow), hit));
  EXPECT_EQ(world_.state_hash(), hash);
  EXPECT_NEAR(world_.body_state(target_body_).value().position.x(), walked_x(kNow), kEps);

  LagCompensationConfig off = config_;
  off.enabled = false;
  LagCompensation uncompensated(off, kRate);
  record_walk(uncompensated, 1, kNow);
  const ViewTime now = uncompensated.resolve(kNow, kNow - 6, 0, 66.7);
  EXPECT_FALSE(shoot(uncompensated, now, walked_x(kNow - 6), hit));
}

TEST_F(LagCompensationTest, WallBlocksTheRewoundTarget) {
  physics::BoxDef wall;
  wall.center = Vec3(walked_x(kNow - 6), 1, 5);
  wall.half_extents = Vec3(2, 2, Real(0.1));
  const physics::ShapeId wall_id = world_.add_box(wall).value();
  LagCompensation lag(config_, kRate);
  record_walk(lag, 1, kNow);

  physics::RayHit hit;
  ASSERT_TRUE(shoot(lag, lag.resolve(kNow, kNow - 6, 0, 66.7), walked_x(kNow - 6), hit));
  EXPECT_EQ(hit.target.shape, wall_id);
  EXPECT_TRUE(hit.target.body.is_null());
  EXPECT_NEAR(hit.distance, Real(4.9), kEps);
}

TEST_F(LagCompensationTest, ClaimOutsideTheWindowIsClampedAndCounted) {
  LagCompensation lag(config_, kRate);
  record_walk(lag, 1, kNow);
  // Estimate 16.7 + 33.3 = 50 ms; a claim of 500 ms is clamped to 50 + 200 = 250 ms.
  const ViewTime view = lag.resolve(kNow, kNow - 30, 0, 16.7);
  EXPECT_TRUE(view.clamped);
  EXPECT_NEAR(view.rewind_ms, 250.0, 1e-3);
  EXPECT_EQ(lag.clamped_claims(), 1u);
  EXPECT_NEAR(target_at(lag, view).x(), walked_x(kNow - 15), kEps);

  // Within 200 ms of the estimate: trusted as it is, not counted.
  const ViewTime trusted = lag.resolve(kNow, kNow - 12, 0, 16.7);
  EXPECT_FALSE(trusted.clamped);
  EXPECT_EQ(trusted.tick, kNow - 12);
  EXPECT_EQ(lag.clamped_claims(), 1u);
}

TEST_F(LagCompensationTest, ShooterIsNeverRewound) {
  LagCompensation lag(config_, kRate);
  // The shooter walks beside the target at z = 5, in front of it on the ray; at tick 54 it
  // stood exactly where the shot passes.
  for (std::uint32_t tick = 1; tick <= kNow; ++tick) {
    const LagSample players[] = {sample(kShooter, Vec3(walked_x(tick), 1, 5)),
                                 sample(kTarget, Vec3(walked_x(tick), 1, 0))};
    lag.record(tick, players);
  }
  const ViewTime view = lag.resolve(kNow, kNow - 6, 0, 66.7);
  std::vector<physics::SphereProxy> spheres;
  lag.rewound_targets(view, kShooter, spheres);
  ASSERT_EQ(spheres.size(), 1u);
  EXPECT_EQ(spheres[0].user_data, kTarget);

  physics::RayHit hit;
  ASSERT_TRUE(shoot(lag, view, walked_x(kNow - 6), hit));
  EXPECT_EQ(hit.target.user_data, kTarget);

  // Someone else's shot does see the first shooter rewound.
  lag.rewound_targets(view, kTarget, spheres);
  ASSERT_EQ(spheres.size(), 1u);
  EXPECT_EQ(spheres[0].user_data, kShooter);
  EXPECT_NEAR(spheres[0].center.x(), walked_x(kNow - 6), kEps);
}

TEST_F(LagCompensationTest, InterpolatesBetweenTicks) {
  LagCompensation lag(config_, kRate);
  record_walk(lag, 1, kNow);
  const ViewTime half = lag.resolve(kNow, kNow - 6, 128, 66.7);
  EXPECT_EQ(half.tick, kNow - 6);
  EXPECT_EQ(half.fraction, 0.5f);
  EXPECT_NEAR(half.rewind_ms, 5.5 * 1000.0 / kRate, 1e-6);
  EXPECT_NEAR(target_at(lag, half).x(), walked_x(kNow - 6) + Real(0.05), kEps);

  // 0.39 m right of the half-way centre: a hit; 0.44 m right of the whole-tick one: a miss.
  physics::RayHit hit;
  const Real x = walked_x(kNow - 6) + Real(0.44);
  EXPECT_TRUE(shoot(lag, half, x, hit));
  EXPECT_FALSE(shoot(lag, lag.resolve(kNow, kNow - 6, 0, 66.7), x, hit));
}

TEST_F(LagCompensationTest, NeverExtrapolatesAClaimAheadOfNow) {
  LagCompensation lag(config_, kRate);
  record_walk(lag, 1, kNow);
  const ViewTime view = lag.resolve(kNow, kNow + 5, 0, 10);
  EXPECT_TRUE(view.clamped);
  EXPECT_EQ(view.tick, kNow);
  EXPECT_EQ(view.fraction, 0.0f);
  EXPECT_EQ(view.rewind_ms, 0.0);
  EXPECT_NEAR(target_at(lag, view).x(), walked_x(kNow), kEps);

  // A view handed in past the newest tick stays at the newest tick.
  ViewTime ahead;
  ahead.tick = kNow + 10;
  ahead.fraction = 0.5f;
  EXPECT_NEAR(target_at(lag, ahead).x(), walked_x(kNow), kEps);
}

TEST_F(LagCompensationTest, RewindIsCappedAt250Ms) {
  LagCompensation lag(config_, kRate);
  record_walk(lag, 1, kNow);
  // No claim, 400 ms one way: the estimate alone is capped, which is not a clamped claim.
  const ViewTime estimate = lag.resolve(kNow, 0, 0, 400);
  EXPECT_FALSE(estimate.clamped);
  EXPECT_NEAR(estimate.rewind_ms, 250.0, 1e-3);
  EXPECT_NEAR(target_at(lag, estimate).x(), walked_x(kNow - 15), kEps);

  // A claim of 300 ms, within 200 ms of the (capped) estimate, is still capped.
  const ViewTime claim = lag.resolve(kNow, kNow - 18, 0, 216.7);
  EXPECT_TRUE(claim.clamped);
  EXPECT_NEAR(claim.rewind_ms, 250.0, 1e-3);
}

TEST_F(LagCompensationTest, TeleportCancelsTheRewind) {
  LagCompensation lag(config_, kRate);
  record_walk(lag, 1, kNow - 4);
  // At tick 57 the target respawns at x = 20 (its life bumps) and stays there.
  for (std::uint32_t tick = kNow - 3; tick <= kNow; ++tick) {
    const LagSample players[] = {sample(kShooter, Vec3(0, 1, 10)),
                                 sample(kTarget, Vec3(20, 1, 0), 1)};
    lag.record(tick, players);
  }
  const ViewTime view = lag.resolve(kNow, kNow - 6, 0, 66.7);
  EXPECT_NEAR(target_at(lag, view).x(), 20, kEps);
  physics::RayHit hit;
  EXPECT_FALSE(shoot(lag, view, walked_x(kNow - 6), hit));
  EXPECT_TRUE(shoot(lag, view, 20, hit));

  // Between the last tick before the teleport and the first after it: where it is now.
  const ViewTime across = lag.resolve(kNow, kNow - 4, 128, 40);
  EXPECT_FALSE(across.clamped);
  EXPECT_NEAR(target_at(lag, across).x(), 20, kEps);
}

TEST_F(LagCompensationTest, DisabledTestsTheCurrentPositions) {
  LagCompensationConfig off = config_;
  off.enabled = false;
  LagCompensation lag(off, kRate);
  record_walk(lag, 1, kNow);
  const ViewTime view = lag.resolve(kNow, kNow - 6, 0, 66.7);
  EXPECT_EQ(view.tick, kNow);
  EXPECT_EQ(view.rewind_ms, 0.0);
  EXPECT_FALSE(view.clamped);
  // Even a view handed in from elsewhere is not rewound.
  ViewTime past;
  past.tick = kNow - 6;
  EXPECT_NEAR(target_at(lag, past).x(), walked_x(kNow), kEps);
  physics::RayHit hit;
  EXPECT_FALSE(shoot(lag, view, walked_x(kNow - 6), hit));
  ASSERT_TRUE(shoot(lag, view, walked_x(kNow), hit));
  EXPECT_EQ(hit.target.user_data, kTarget);
}

TEST_F(LagCompensationTest, ClaimOlderThanTheRingIsClamped) {
  LagCompensation lag(config_, kRate);
  constexpr std::uint32_t kLate = 200;
  record_walk(lag, 1, kLate);
  // Tick 10 was 3.2 s ago, long out of the 1 s ring: clamped to 50 + 200 = 250 ms.
  const ViewTime view = lag.resolve(kLate, 10, 0, 16.7);
  EXPECT_TRUE(view.clamped);
  EXPECT_EQ(lag.clamped_claims(), 1u);
  EXPECT_NEAR(view.rewind_ms, 250.0, 1e-3);
  EXPECT_NEAR(target_at(lag, view).x(), walked_x(kLate - 15), kEps);

  // A view older than the ring, handed in as it is, takes the oldest stored tick (1 s + now).
  ViewTime old;
  old.tick = 10;
  EXPECT_NEAR(target_at(lag, old).x(), walked_x(kLate - kRate), kEps);
}

TEST(LagCompensationConfigTest, ValidateNamesTheFieldAndTheRange) {
  EXPECT_EQ(LagCompensationConfig{}.validate(), "");
  LagCompensationConfig config;
  config.history_s = 0.05f;
  EXPECT_NE(config.validate().find("history_s must be 0.1..2, got 0.05"), std::string::npos)
      << config.validate();
  config = {};
  config.max_rewind_ms = 1500;
  EXPECT_NE(config.validate().find("max_rewind_ms must be 0..1000"), std::string::npos)
      << config.validate();
  config = {};
  config.claim_tolerance_ms = -1;
  EXPECT_NE(config.validate().find("claim_tolerance_ms"), std::string::npos);
  config = {};
  config.interpolation_delay_ms = 300;
  EXPECT_NE(config.validate().find("interpolation_delay_ms must be 0..250"), std::string::npos);
}

}  // namespace
}  // namespace ricochet::server::lag_compensation_test
