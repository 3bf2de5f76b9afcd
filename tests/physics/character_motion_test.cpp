// Character motion (character_motion.h): the wished speed and direction, ground and air, the
// ground test on other bodies, and the determinism a client's prediction relies on.

#include "ricochet/physics/character_motion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "ricochet/physics/scene_profile.h"

namespace ricochet::physics::character_motion_test {
namespace {

constexpr float kDt = 1.0f / 60;

/// A floor at y = 0 and one character on it.
struct Walker {
  World world = World::create(profiles::arena_players()).value();
  BodyId body;
  CharacterMotionConfig config;
  Real radius = character_body_def(Vec3::Zero()).radius;

  explicit Walker(const Vec3& start = Vec3(0, Real(0.4), 0)) {
    EXPECT_TRUE(world.add_plane(PlaneDef{}).ok());
    body = world.create_body(character_body_def(start)).value();
  }
  void step(const CharacterIntent& intent) {
    const bool grounded = is_grounded(world, body, radius, config);
    const Vec3 velocity = world.body_state(body).value().linear_velocity;
    ASSERT_TRUE(
        world.set_linear_velocity(body, character_velocity(config, intent, velocity, grounded, kDt))
            .ok());
    ASSERT_TRUE(world.step(kDt).ok());
  }
  BodyState state() const { return world.body_state(body).value(); }
  Real horizontal_speed() const {
    const Vec3 v = state().linear_velocity;
    return std::hypot(v.x(), v.z());
  }
};

CharacterIntent walk(float yaw_rad, float right, float forward, bool jump = false) {
  return {yaw_wish_direction(yaw_rad, right, forward), stick_speed_fraction(right, forward), jump};
}

TEST(CharacterMotion, TheStickTurnsWithTheYaw) {
  EXPECT_TRUE(yaw_wish_direction(0, 0, 1).isApprox(Vec3(0, 0, -1), Real(1e-6)));
  EXPECT_TRUE(yaw_wish_direction(0, 1, 0).isApprox(Vec3(1, 0, 0), Real(1e-6)));
  EXPECT_TRUE(yaw_wish_direction(float(M_PI / 2), 0, 1).isApprox(Vec3(-1, 0, 0), Real(1e-6)));
  // A diagonal is one unit long and moves at full speed, not 1.41 times it.
  EXPECT_NEAR(yaw_wish_direction(0.3f, 1, 1).norm(), 1, 1e-6);
  EXPECT_FLOAT_EQ(stick_speed_fraction(1, 1), 1);
  EXPECT_FLOAT_EQ(stick_speed_fraction(0, 0.5f), 0.5f);
  EXPECT_EQ(yaw_wish_direction(1, 0, 0), Vec3::Zero());
}

TEST(CharacterMotion, HalfAStickIsHalfTheSpeed) {
  Walker half;
  for (int k = 0; k < 90; ++k) half.step(walk(0, 0, 0.5f));
  EXPECT_NEAR(half.horizontal_speed(), 3.5, 1e-3);
}

TEST(CharacterMotion, NoIntentStopsOnTheGroundButNotInTheAir) {
  CharacterMotionConfig config;
  const Vec3 moving(5, 0, 0);
  // On the ground friction takes friction * speed * dt.
  EXPECT_NEAR(character_velocity(config, {}, moving, true, kDt).x(), 5 * (1 - 6 * kDt), 1e-5);
  EXPECT_EQ(character_velocity(config, {}, moving, false, kDt), moving);
}

TEST(CharacterMotion, JumpsOnlyFromTheGround) {
  CharacterMotionConfig config;
  const CharacterIntent jump{Vec3::Zero(), 0, true};
  EXPECT_FLOAT_EQ(float(character_velocity(config, jump, Vec3::Zero(), true, kDt).y()), 5);
  EXPECT_EQ(character_velocity(config, jump, Vec3(0, -1, 0), false, kDt).y(), -1);
  // A faster upward speed (a rocket jump) is kept.
  EXPECT_EQ(character_velocity(config, jump, Vec3(0, 8, 0), true, kDt).y(), 8);
}

TEST(CharacterMotion, StandsOnAnotherCharacter) {
  Walker scene(Vec3(0, Real(0.4), 0));
  const BodyId top = scene.world.create_body(character_body_def(Vec3(0, Real(1.2), 0))).value();
  EXPECT_TRUE(is_grounded(scene.world, top, scene.radius, scene.config));
  CharacterMotionConfig config;
  config.ground_probe_m = 0.01f;
  const BodyId high = scene.world.create_body(character_body_def(Vec3(5, Real(0.5), 0))).value();
  EXPECT_FALSE(is_grounded(scene.world, high, scene.radius, config));  // 10 cm up
}

TEST(CharacterMotion, TheSameIntentsGiveTheSameBits) {
  // What prediction relies on: two worlds with the same geometry and intents agree exactly.
  Walker a;
  Walker b;
  for (int k = 0; k < 240; ++k) {
    const CharacterIntent intent = walk(0.01f * float(k), k % 7 < 3 ? 1.0f : -0.4f, 1, k % 50 == 0);
    a.step(intent);
    b.step(intent);
  }
  const BodyState sa = a.state();
  const BodyState sb = b.state();
  EXPECT_EQ(std::memcmp(sa.position.data(), sb.position.data(), sizeof(Real) * 3), 0);
  EXPECT_EQ(std::memcmp(sa.linear_velocity.data(), sb.linear_velocity.data(), sizeof(Real) * 3), 0);
  EXPECT_GT(sa.position.norm(), 5);  // it went somewhere
}

TEST(CharacterMotionConfig, NamesTheWrongField) {
  EXPECT_EQ(CharacterMotionConfig{}.validate(), "");
  CharacterMotionConfig config;
  config.jump_speed_mps = -1;
  EXPECT_EQ(config.validate(), "jump_speed_mps must be 0..100, got -1.000000");
  config = {};
  config.ground_probe_m = std::nanf("");
  EXPECT_NE(config.validate().find("ground_probe_m must be 0.001..1"), std::string::npos);
}

TEST(CharacterBody, IsAFrictionlessPlayer) {
  const BodyDef def = character_body_def(Vec3(1, 2, 3));
  EXPECT_EQ(def.material.friction, 0);
  EXPECT_EQ(def.radius, profiles::player(Vec3::Zero()).radius);
  EXPECT_EQ(def.position, Vec3(1, 2, 3));
}

}  // namespace
}  // namespace ricochet::physics::character_motion_test
