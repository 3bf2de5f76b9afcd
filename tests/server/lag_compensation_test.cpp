// Lag compensation over a real physics world with fake ticks: a target walks along +X at
// 6 m/s (0.1 m per 60 Hz tick), the shooter fires along -Z from z = 10.

#include "ricochet/server/lag_compensation.h"

#include <gtest/gtest.h>

#include <vector>

#include "ricochet/physics/scene_profile.h"
#include "ricochet/server/movement.h"

namespace ricochet::server {
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

}  // namespace
}  // namespace ricochet::server
