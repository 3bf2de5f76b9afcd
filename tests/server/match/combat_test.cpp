// Combat math: damage and armour, the match RNG, aim and spread, explosions, input checks.

#include "ricochet/server/combat.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <vector>

#include "ricochet/physics/scene_profile.h"
#include "ricochet/server/movement.h"

namespace ricochet::server::combat_test {
namespace {

using physics::Real;
using physics::Vec3;

constexpr float kPi = std::numbers::pi_v<float>;

// --- damage and armour ---

TEST(Damage, HealthOnlyWithoutArmor) {
  Vitals vitals;
  const DamageResult result = apply_damage(vitals, 30, 0.66f);
  EXPECT_EQ(result.health_lost, 30);
  EXPECT_EQ(result.armor_lost, 0);
  EXPECT_FALSE(result.killed);
  EXPECT_EQ(vitals.health, 70);
  EXPECT_EQ(vitals.armor, 0);
}

TEST(Damage, ArmorAbsorbsItsShareRoundedHalfUp) {
  Vitals vitals{.health = 100, .armor = 100};
  // 20 × 0.66 = 13.2 → 13 to armour, 7 to health.
  DamageResult result = apply_damage(vitals, 20, 0.66f);
  EXPECT_EQ(result.armor_lost, 13);
  EXPECT_EQ(result.health_lost, 7);
  EXPECT_EQ(vitals.armor, 87);
  EXPECT_EQ(vitals.health, 93);
  // 25 × 0.5 = 12.5 → 13 (halves up).
  vitals = Vitals{.health = 100, .armor = 100};
  result = apply_damage(vitals, 25, 0.5f);
  EXPECT_EQ(result.armor_lost, 13);
  EXPECT_EQ(result.health_lost, 12);
}

TEST(Damage, ArmorRunsOutMidHit) {
  Vitals vitals{.health = 100, .armor = 5};
  // Armour would take 66 but has 5: health takes the other 95.
  const DamageResult result = apply_damage(vitals, 100, 0.66f);
  EXPECT_EQ(result.armor_lost, 5);
  EXPECT_EQ(result.health_lost, 95);
  EXPECT_FALSE(result.killed);
  EXPECT_EQ(vitals.armor, 0);
  EXPECT_EQ(vitals.health, 5);
}

TEST(Damage, ExactlyHundredKills) {
  Vitals vitals;
  const DamageResult result = apply_damage(vitals, 100, 0.66f);
  EXPECT_TRUE(result.killed);
  EXPECT_EQ(result.health_lost, 100);
  EXPECT_EQ(vitals.health, 0);
  // 99 does not.
  Vitals other;
  EXPECT_FALSE(apply_damage(other, 99, 0.66f).killed);
  EXPECT_EQ(other.health, 1);
}

TEST(Damage, OverkillCountsOnlyWhatWasLeft) {
  Vitals vitals{.health = 30, .armor = 0};
  const DamageResult result = apply_damage(vitals, 100, 0.66f);
  EXPECT_TRUE(result.killed);
  EXPECT_EQ(result.health_lost, 30);
  EXPECT_EQ(vitals.health, 0);
}

TEST(Damage, DeadTargetsAndNonPositiveDamageChangeNothing) {
  Vitals dead{.health = 0, .armor = 50};
  DamageResult result = apply_damage(dead, 50, 0.66f);
  EXPECT_FALSE(result.killed);
  EXPECT_EQ(result.health_lost, 0);
  EXPECT_EQ(result.armor_lost, 0);
  EXPECT_EQ(dead.armor, 50);

  Vitals alive{.health = 100, .armor = 50};
  result = apply_damage(alive, 0, 0.66f);
  EXPECT_EQ(result.health_lost + result.armor_lost, 0);
  result = apply_damage(alive, -20, 0.66f);
  EXPECT_EQ(result.health_lost + result.armor_lost, 0);
  EXPECT_EQ(alive.health, 100);
  EXPECT_EQ(alive.armor, 50);
}

TEST(Damage, InvariantsOverRandomHits) {
  // Nothing is created or lost: what the target loses is at most the damage, never negative,
  // and health and armour stay within 0..their start, whatever the absorb fraction.
  MatchRng rng(2024);
  for (int i = 0; i < 20000; ++i) {
    Vitals vitals{.health = int(rng.next() % 101), .armor = int(rng.next() % 101)};
    const Vitals before = vitals;
    const int damage = int(rng.next() % 300) - 20;
    const float absorb = rng.uniform() * 1.4f - 0.2f;  // out of range too: clamped
    const DamageResult result = apply_damage(vitals, damage, absorb);
    ASSERT_GE(result.health_lost, 0);
    ASSERT_GE(result.armor_lost, 0);
    ASSERT_LE(result.health_lost + result.armor_lost, std::max(damage, 0));
    ASSERT_EQ(vitals.health, before.health - result.health_lost);
    ASSERT_EQ(vitals.armor, before.armor - result.armor_lost);
    ASSERT_GE(vitals.health, 0);
    ASSERT_GE(vitals.armor, 0);
    ASSERT_EQ(result.killed, before.health > 0 && vitals.health == 0);
  }
  Vitals vitals{.health = 100, .armor = 100};
  EXPECT_EQ(apply_damage(vitals, 10, std::nanf("")).armor_lost, 0);
}

TEST(Damage, ScaleForSelfTeammatesAndOthers) {
  WeaponsConfig config;
  EXPECT_FLOAT_EQ(damage_scale(config, true, false), 0.5f);
  EXPECT_FLOAT_EQ(damage_scale(config, true, true), 0.5f);  // oneself is never a teammate
  EXPECT_FLOAT_EQ(damage_scale(config, false, true), 0.0f);
  EXPECT_FLOAT_EQ(damage_scale(config, false, false), 1.0f);
  config.friendly_fire = true;
  EXPECT_FLOAT_EQ(damage_scale(config, false, true), 0.5f);

  EXPECT_EQ(scaled_damage(100, 0.5f), 50);
  EXPECT_EQ(scaled_damage(25, 0.5f), 13);
  EXPECT_EQ(scaled_damage(40, 0.0f), 0);
  EXPECT_EQ(scaled_damage(40, 1.0f), 40);
  EXPECT_EQ(scaled_damage(-3, 1.0f), 0);
  EXPECT_EQ(scaled_damage(40, 1e30f), 40);
  EXPECT_EQ(scaled_damage(40, std::nanf("")), 0);
}

// --- random numbers ---

TEST(MatchRng, SameSeedSameSequenceOtherSeedOther) {
  MatchRng a(42), b(42), c(43);
  bool differs = false;
  for (int i = 0; i < 1000; ++i) {
    const std::uint64_t x = a.next();
    EXPECT_EQ(x, b.next());
    differs = differs || x != c.next();
  }
  EXPECT_TRUE(differs);
}

TEST(MatchRng, PinnedSequenceForSeedOne) {
  // xoshiro256** seeded by splitmix64(1), computed independently: a change of generator (which
  // would change every replay) fails here.
  MatchRng rng(1);
  EXPECT_EQ(rng.next(), 0xb3f2af6d0fc710c5ull);
  EXPECT_EQ(rng.next(), 0x853b559647364ceaull);
  EXPECT_EQ(rng.next(), 0x92f89756082a4514ull);
  MatchRng zero(0);
  EXPECT_NE(zero.next(), 0u);  // splitmix64 seeding: seed 0 is a good state
}

TEST(MatchRng, UniformInUnitIntervalWithMeanHalf) {
  MatchRng rng(7);
  double sum = 0;
  for (int i = 0; i < 10000; ++i) {
    const float u = rng.uniform();
    ASSERT_GE(u, 0.0f);
    ASSERT_LT(u, 1.0f);
    sum += u;
  }
  EXPECT_NEAR(sum / 10000, 0.5, 0.01);
}

// --- aim ---

TEST(Aim, DirectionAxes) {
  auto expect_near = [](const Vec3& a, const Vec3& b) {
    EXPECT_LT((a - b).norm(), 1e-5) << a.transpose() << " vs " << b.transpose();
  };
  expect_near(aim_direction(0, 0), Vec3(0, 0, -1));
  expect_near(aim_direction(kPi / 2, 0), Vec3(-1, 0, 0));  // counter-clockwise from above
  expect_near(aim_direction(-kPi / 2, 0), Vec3(1, 0, 0));
  expect_near(aim_direction(kPi, 0), Vec3(0, 0, 1));
  expect_near(aim_direction(0, kPi / 2), Vec3(0, 1, 0));
  expect_near(aim_direction(0, -kPi / 2), Vec3(0, -1, 0));
  expect_near(aim_direction(0, kPi / 4), Vec3(0, std::sqrt(0.5f), -std::sqrt(0.5f)));
  EXPECT_NEAR(aim_direction(1.3f, -0.7f).norm(), 1, 1e-6);
}

TEST(Aim, MatchesMovementForward) {
  // Walking forward (movement.h) and shooting level go the same way.
  PlayerInput input;
  input.move_forward = 1;
  input.yaw_rad = 0.8f;
  EXPECT_LT((wish_direction(input) - aim_direction(0.8f, 0)).norm(), 1e-5);
}

TEST(Aim, EyeIsAboveCentre) {
  EXPECT_EQ(eye_position(Vec3(1, 2, 3)), Vec3(1, 2.25f, 3));
}

TEST(Spread, ZeroSpreadIsExactAndDrawsNothing) {
  MatchRng rng(5), untouched(5);
  const Vec3 aim = aim_direction(0.3f, 0.2f);
  EXPECT_LT((spread_direction(aim * 3, 0, rng) - aim).norm(), 1e-6);
  EXPECT_EQ(rng.next(), untouched.next());
}

TEST(Spread, InsideConeMeanIsAimAndDeterministic) {
  const float spread = 0.05f;
  const Vec3 aim = aim_direction(2.0f, -0.4f);
  MatchRng rng(99), replay(99);
  Vec3 sum = Vec3::Zero();
  double cos_sum = 0;
  for (int i = 0; i < 10000; ++i) {
    const Vec3 d = spread_direction(aim, spread, rng);
    ASSERT_NEAR(d.norm(), 1, 1e-5);
    const Real cos_angle = d.dot(aim);
    ASSERT_GE(cos_angle, std::cos(spread) - 1e-6);
    ASSERT_EQ(d, spread_direction(aim, spread, replay));
    sum += d;
    cos_sum += cos_angle;
  }
  // The mean direction is the aim (within 1/10 of the cone).
  EXPECT_LT(std::acos(std::min(Real(1), sum.normalized().dot(aim))), spread / 10);
  // Uniform over the cap: the mean of cos θ is halfway between cos spread and 1.
  EXPECT_NEAR(cos_sum / 10000, (1 + std::cos(spread)) / 2, 2e-5);
}

TEST(Spread, WorksAroundVerticalAim) {
  MatchRng rng(3);
  const Vec3 up(0, 1, 0);
  for (int i = 0; i < 100; ++i) {
    const Vec3 d = spread_direction(up, 0.1f, rng);
    EXPECT_GE(d.dot(up), std::cos(0.1f) - 1e-6);
  }
}

// --- explosions ---

class ExplosionTest : public ::testing::Test {
 protected:
  ExplosionTest() : world_(physics::World::create(combat_world_def()).value()) {
    weapon_ = WeaponsConfig{}[WeaponKind::RocketLauncher];  // 100 damage, 3.5 m, 600 N·s
  }

  std::vector<ExplosionEffect> explode(const Vec3& center,
                                       std::span<const ExplosionTarget> targets) {
    std::vector<ExplosionEffect> out;
    explosion_effects(world_, center, weapon_, targets, out);
    return out;
  }

  physics::World world_;
  WeaponConfig weapon_;
};

TEST_F(ExplosionTest, FalloffAtZeroHalfAndFullRadius) {
  const Real r = Real(0.4);
  // Surface distances 0 (centre inside), 1.75 (half radius), 3.5 (full: out of reach), 0.35.
  const std::vector<ExplosionTarget> targets = {
      {physics::BodyId{1, 1}, Vec3(0.2f, 0, 0), float(r)},
      {physics::BodyId{2, 1}, Vec3(1.75f + r, 0, 0), float(r)},
      {physics::BodyId{3, 1}, Vec3(-(3.5f + r), 0, 0), float(r)},
      {physics::BodyId{4, 1}, Vec3(0, 0, 0.35f + r), float(r)},
  };
  const std::vector<ExplosionEffect> effects = explode(Vec3::Zero(), targets);
  ASSERT_EQ(effects.size(), 3u);
  EXPECT_EQ(effects[0].target, 0u);
  EXPECT_EQ(effects[0].damage, 100);
  EXPECT_NEAR(effects[0].impulse_ns.norm(), 600, 1e-2);
  EXPECT_EQ(effects[1].target, 1u);
  EXPECT_EQ(effects[1].damage, 50);
  EXPECT_NEAR(effects[1].impulse_ns.norm(), 300, 1e-2);
  EXPECT_EQ(effects[2].target, 3u);
  EXPECT_EQ(effects[2].damage, 90);
  EXPECT_NEAR(effects[2].impulse_ns.norm(), 540, 1e-2);
}

TEST_F(ExplosionTest, JustInsideRadiusReachesJustOutsideDoesNot) {
  const std::vector<ExplosionTarget> targets = {
      {physics::BodyId{1, 1}, Vec3(3.49f, 0, 0), 0},
      {physics::BodyId{2, 1}, Vec3(3.51f, 0, 0), 0},
  };
  const std::vector<ExplosionEffect> effects = explode(Vec3::Zero(), targets);
  ASSERT_EQ(effects.size(), 1u);
  EXPECT_EQ(effects[0].target, 0u);
  EXPECT_EQ(effects[0].damage, 0);  // 100 × 0.01/3.5 rounds to 0; the push is still there
  EXPECT_GT(effects[0].impulse_ns.norm(), 0);
}

TEST_F(ExplosionTest, ImpulsePointsAwayWithUpwardBias) {
  const std::vector<ExplosionTarget> targets = {
      {physics::BodyId{1, 1}, Vec3(2, 0, 0), 0.4f},     // beside
      {physics::BodyId{2, 1}, Vec3(0, 0.3f, 0), 0.4f},  // standing on the blast: rocket jump
      {physics::BodyId{3, 1}, Vec3(0, 0, 0), 0.4f},     // centred on it
  };
  const std::vector<ExplosionEffect> effects = explode(Vec3::Zero(), targets);
  ASSERT_EQ(effects.size(), 3u);
  const Vec3 beside = effects[0].impulse_ns.normalized();
  EXPECT_GT(beside.x(), 0.9);
  EXPECT_NEAR(beside.y() / beside.x(), kKnockbackUpwardBias, 1e-4);
  EXPECT_NEAR(beside.z(), 0, 1e-6);
  EXPECT_LT((effects[1].impulse_ns.normalized() - Vec3::UnitY()).norm(), 1e-5);
  EXPECT_NEAR(effects[1].impulse_ns.norm(), 600, 1e-2);
  EXPECT_LT((effects[2].impulse_ns.normalized() - Vec3::UnitY()).norm(), 1e-5);
}

TEST_F(ExplosionTest, WallBlocksLineOfSight) {
  physics::BoxDef wall;
  wall.center = Vec3(1, 0, 0);
  wall.half_extents = Vec3(0.1f, 3, 3);
  ASSERT_TRUE(world_.add_box(wall).ok());
  const std::vector<ExplosionTarget> targets = {
      {physics::BodyId{1, 1}, Vec3(2, 0, 0), 0.4f},   // behind the wall
      {physics::BodyId{2, 1}, Vec3(-2, 0, 0), 0.4f},  // in the open
  };
  const std::vector<ExplosionEffect> effects = explode(Vec3::Zero(), targets);
  ASSERT_EQ(effects.size(), 1u);
  EXPECT_EQ(effects[0].target, 1u);
}

TEST_F(ExplosionTest, LiveBodiesDoNotBlock) {
  // A player between the blast and another shields nothing: only statics block.
  const physics::BodyId front = world_.create_body(player_body_def(Vec3(1, 0, 0))).value();
  const physics::BodyId back = world_.create_body(player_body_def(Vec3(2, 0, 0))).value();
  const std::vector<ExplosionTarget> targets = {{front, Vec3(1, 0, 0), 0.4f},
                                                {back, Vec3(2, 0, 0), 0.4f}};
  EXPECT_EQ(explode(Vec3::Zero(), targets).size(), 2u);
}

TEST_F(ExplosionTest, AppendsAndSkipsNonFiniteTargets) {
  const std::vector<ExplosionTarget> targets = {
      {physics::BodyId{1, 1}, Vec3(std::nanf(""), 0, 0), 0.4f},
      {physics::BodyId{2, 1}, Vec3(1, 0, 0), 0.4f},
  };
  std::vector<ExplosionEffect> out(1);
  explosion_effects(world_, Vec3::Zero(), weapon_, targets, out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[1].target, 1u);
}

TEST_F(ExplosionTest, ZeroRadiusWeaponReachesNobody) {
  const ExplosionTarget target{physics::BodyId{1, 1}, Vec3::Zero(), 0.4f};
  weapon_ = WeaponsConfig{}[WeaponKind::Rifle];
  EXPECT_TRUE(explode(Vec3::Zero(), std::span(&target, 1)).empty());
}

TEST(ExplosionSpeedCap, KeepsTheDirectionAndNeverPassesTheCapOrSlowsAFasterBody) {
  const Vec3 still = Vec3::Zero();
  EXPECT_EQ(capped_explosion_velocity(still, Vec3(3, 4, 0), 64), Vec3(3, 4, 0));
  const Vec3 capped = capped_explosion_velocity(still, Vec3(0, 300, 400), 64);
  EXPECT_NEAR(capped.norm(), 64, 1e-4);
  EXPECT_NEAR(capped.y() / capped.z(), 0.75, 1e-6);
  // Already faster than the cap (a long fall): the push may turn it but not speed it up.
  const Vec3 falling(0, -80, 0);
  EXPECT_NEAR(capped_explosion_velocity(falling, Vec3(100, -80, 0), 64).norm(), 80, 1e-4);
  EXPECT_EQ(capped_explosion_velocity(falling, Vec3(0, -70, 0), 64), Vec3(0, -70, 0));
}

TEST_F(ExplosionTest, RocketAgainstWallExplodesOffTheSurfaceAndPushesShooterBack) {
  physics::BoxDef wall;
  wall.center = Vec3(0, 2, -3);
  wall.half_extents = Vec3(5, 2, 0.1f);  // face at z = -2.9
  ASSERT_TRUE(world_.add_box(wall).ok());
  const physics::BodyId shooter = world_.create_body(player_body_def(Vec3(0, 1, -1.5f))).value();
  const Vec3 eye = eye_position(Vec3(0, 1, -1.5f));
  ASSERT_TRUE(
      world_.create_projectile(rocket_projectile(weapon_, eye, Vec3(0, 0, -1), shooter, 1)).ok());
  std::optional<physics::ProjectileHitEvent> hit;
  for (int step = 0; step < 30 && !hit; ++step) {
    ASSERT_TRUE(world_.step(Real(1.0 / 60)).ok());
    if (!world_.projectile_hit_events().empty()) hit = world_.projectile_hit_events()[0];
  }
  ASSERT_TRUE(hit.has_value());
  const Vec3 center = explosion_center(*hit, weapon_);
  EXPECT_NEAR(center.z(), -2.8, 1e-3);  // 0.1 m (the rocket's radius) off the face
  const Vec3 at = world_.body_state(shooter).value().position;
  const ExplosionTarget target{shooter, at, 0.4f};
  const std::vector<ExplosionEffect> effects = explode(center, std::span(&target, 1));
  ASSERT_EQ(effects.size(), 1u);
  EXPECT_GT(effects[0].damage, 0);
  EXPECT_GT(effects[0].impulse_ns.z(), 0);  // away from the wall
  EXPECT_TRUE(world_.apply_impulse(shooter, effects[0].impulse_ns, at).ok());
  EXPECT_GT(world_.body_state(shooter).value().linear_velocity.z(), 1);
}

// --- input checks ---

TEST(InputChecks, ViolationNames) {
  EXPECT_STREQ(name(Violation::TurnRate), "turn_rate");
  EXPECT_STREQ(name(Violation::FireRate), "fire_rate");
  EXPECT_STREQ(name(Violation::InputRate), "input_rate");
  EXPECT_STREQ(name(Violation::ViewTick), "view_tick");
}

TEST(InputChecks, TurnRateWithinAndBeyond) {
  const float max = 1.0f;  // 60 rad/s at 60 Hz
  EXPECT_TRUE(turn_rate_ok(0, 0, 0.9f, 0, max));
  EXPECT_TRUE(turn_rate_ok(0, 0, -1.0f, 1.0f, max));
  EXPECT_FALSE(turn_rate_ok(0, 0, 1.1f, 0, max));
  EXPECT_FALSE(turn_rate_ok(0, 0.2f, 0, -0.9f, max));  // pitch
}

TEST(InputChecks, TurnRateYawWrapsAround) {
  const float max = 0.2f;
  EXPECT_TRUE(turn_rate_ok(3.1f, 0, -3.1f, 0, max));  // 0.083 rad the short way
  EXPECT_TRUE(turn_rate_ok(-3.1f, 0, 3.1f, 0, max));
  EXPECT_TRUE(turn_rate_ok(2 * kPi - 0.05f, 0, 0.05f, 0, max));
  EXPECT_TRUE(turn_rate_ok(-2 * kPi + 0.05f, 0, 2 * kPi - 0.05f, 0, max));  // 4π - 0.1 apart
  EXPECT_FALSE(turn_rate_ok(0, 0, kPi, 0, max));
  EXPECT_FALSE(turn_rate_ok(0, 0, -kPi, 0, max));
}

TEST(InputChecks, TurnRateRefusesNonFinite) {
  EXPECT_FALSE(turn_rate_ok(std::nanf(""), 0, 0, 0, 1));
  EXPECT_FALSE(turn_rate_ok(0, 0, 0, INFINITY, 1));
}

TEST(InputChecks, InputRateLimit) {
  EXPECT_EQ(input_rate_limit(60), 83);
  EXPECT_EQ(input_rate_limit(128), 168);
  EXPECT_EQ(input_rate_limit(10), 20);
}

}  // namespace
}  // namespace ricochet::server::combat_test
