// Weapon configuration and validation; rockets and grenades as physics objects in the match world.

#include "ricochet/server/weapons.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "ricochet/physics/scene_profile.h"
#include "ricochet/server/movement.h"

namespace ricochet::server::weapons_test {
namespace {

using physics::Real;
using physics::Vec3;
namespace profiles = physics::profiles;

constexpr Real kDt = Real(1.0 / 60);

const WeaponConfig& default_weapon(WeaponKind kind) {
  static const WeaponsConfig config;
  return config[kind];
}

physics::World combat_world() {
  physics::World world = physics::World::create(combat_world_def()).value();
  EXPECT_TRUE(world.add_plane(physics::PlaneDef{}).ok());  // floor at y = 0
  return world;
}

TEST(WeaponsConfig, DefaultsAreValid) {
  const WeaponsConfig config;
  EXPECT_EQ(config.validate(), "");
  EXPECT_EQ(config[WeaponKind::Rifle].damage, 20);
  EXPECT_FLOAT_EQ(config[WeaponKind::Rifle].fire_interval_s, 0.1f);
  EXPECT_FLOAT_EQ(config[WeaponKind::RocketLauncher].projectile_speed_mps, 25);
  EXPECT_FLOAT_EQ(config[WeaponKind::GrenadeLauncher].restitution, 0.6f);
  EXPECT_FLOAT_EQ(config[WeaponKind::GrenadeLauncher].fuse_s, 2);
}

TEST(WeaponsConfig, ValidationNamesWeaponFieldRangeAndValue) {
  WeaponsConfig config;
  config.weapons[0].fire_interval_s = 0;
  EXPECT_EQ(config.validate(), "rifle fire_interval_s must be 0.01..10, got 0.000000");

  config = WeaponsConfig{};
  config.weapons[1].damage = -5;
  EXPECT_EQ(config.validate(), "rocket_launcher damage must be 0..1000, got -5");

  config = WeaponsConfig{};
  config.weapons[2].restitution = std::nanf("");
  EXPECT_EQ(config.validate(), "grenade_launcher restitution must be 0..1, got nan");

  config = WeaponsConfig{};
  config.weapons[0].ammo_start = 201;
  EXPECT_EQ(config.validate(), "rifle ammo_start must be 0..ammo_max, got 201");

  config = WeaponsConfig{};
  config.weapons[0].spread_rad = 1;
  EXPECT_EQ(config.validate(), "rifle spread_rad must be 0..0.5, got 1.000000");

  config = WeaponsConfig{};
  config.armor_absorb = 1.5f;
  EXPECT_EQ(config.validate(), "weapons armor_absorb must be 0..1, got 1.500000");

  config = WeaponsConfig{};
  config.max_turn_rate_rad_s = 0;
  EXPECT_EQ(config.validate(), "weapons max_turn_rate_rad_s must be 1..10000, got 0.000000");

  config = WeaponsConfig{};
  config.self_damage_scale = -0.1f;
  EXPECT_NE(config.validate().find("self_damage_scale must be 0..1"), std::string::npos);
}

TEST(WeaponsConfig, ProjectileWeaponsNeedSpeedFuseAndGrenadeRadius) {
  WeaponsConfig config;
  config.weapons[1].projectile_speed_mps = 0;
  EXPECT_EQ(config.validate(),
            "rocket_launcher projectile_speed_mps must be 1..1000, got 0.000000");

  config = WeaponsConfig{};
  config.weapons[2].fuse_s = 0;
  EXPECT_EQ(config.validate(), "grenade_launcher fuse_s must be 0.05..60, got 0.000000");

  config = WeaponsConfig{};
  config.weapons[2].projectile_radius_m = 0;
  EXPECT_EQ(config.validate(),
            "grenade_launcher projectile_radius_m must be 0.01..1, got 0.000000");

  // The rifle shoots no projectile: zero projectile fields are fine for it.
  EXPECT_EQ(WeaponsConfig{}[WeaponKind::Rifle].validate("rifle"), "");
}

TEST(Weapons, NamesAndSlots) {
  EXPECT_STREQ(name(WeaponKind::Rifle), "rifle");
  EXPECT_STREQ(name(WeaponKind::RocketLauncher), "rocket_launcher");
  EXPECT_STREQ(name(WeaponKind::GrenadeLauncher), "grenade_launcher");
  EXPECT_EQ(weapon_for_slot(0), std::nullopt);
  EXPECT_EQ(weapon_for_slot(1), WeaponKind::Rifle);
  EXPECT_EQ(weapon_for_slot(2), WeaponKind::RocketLauncher);
  EXPECT_EQ(weapon_for_slot(3), WeaponKind::GrenadeLauncher);
  EXPECT_EQ(weapon_for_slot(4), std::nullopt);
  EXPECT_EQ(weapon_for_slot(9), std::nullopt);
  for (std::size_t k = 0; k < kWeaponCount; ++k) {
    const auto kind = static_cast<WeaponKind>(k);
    EXPECT_EQ(weapon_for_slot(proto::slot_of(to_wire(kind))), kind);
  }
}

TEST(Weapons, TheJoinReplyCarriesEachWeaponsFlight) {
  WeaponsConfig config;
  config.weapons[2].gravity_scale = 0.5f;
  config.weapons[1].projectile_speed_mps = 40;
  const std::vector<wire::WeaponSpec> specs = weapon_specs(config);
  ASSERT_EQ(specs.size(), kWeaponCount);
  const float g = static_cast<float>(combat_world_def().gravity.y());
  ASSERT_LT(g, 0);
  const auto gravity = [](const wire::WeaponSpec& spec) {
    return std::vector<float>(spec.gravity_mps2().begin(), spec.gravity_mps2().end());
  };
  const std::vector<float> none{0, 0, 0};

  EXPECT_EQ(specs[0].weapon(), wire::WEAPON_RIFLE);
  EXPECT_EQ(specs[0].projectile_speed_mps(), 0.0f);  // hitscan
  EXPECT_EQ(specs[0].range_m(), config.weapons[0].range_m);
  EXPECT_EQ(specs[0].fire_interval_s(), config.weapons[0].fire_interval_s);
  EXPECT_EQ(gravity(specs[0]), none);

  EXPECT_EQ(specs[1].weapon(), wire::WEAPON_ROCKET_LAUNCHER);
  EXPECT_EQ(specs[1].projectile_speed_mps(), 40.0f);
  EXPECT_EQ(specs[1].range_m(), 0.0f);
  EXPECT_EQ(specs[1].explosion_radius_m(), config.weapons[1].explosion_radius_m);
  EXPECT_EQ(gravity(specs[1]), none);
  EXPECT_FALSE(std::signbit(specs[1].gravity_mps2(1)));  // no -0 on the wire

  EXPECT_EQ(specs[2].weapon(), wire::WEAPON_GRENADE_LAUNCHER);
  EXPECT_EQ(specs[2].projectile_speed_mps(), config.weapons[2].projectile_speed_mps);
  EXPECT_EQ(gravity(specs[2]), (std::vector<float>{0, 0.5f * g, 0}));
}

TEST(Weapons, CombatWorldIsArenaPlayersWithRestitution) {
  const physics::WorldDef def = combat_world_def();
  EXPECT_EQ(def.validate(), "");
  EXPECT_TRUE(def.enable_restitution);
  EXPECT_FALSE(def.enable_rotation);
  EXPECT_FALSE(def.enable_sleep);
  EXPECT_EQ(def.iterations, profiles::arena_players().iterations);
}

TEST(Rocket, DefinitionUsesWeaponAndLayers) {
  const WeaponConfig& rocket = default_weapon(WeaponKind::RocketLauncher);
  const physics::BodyId shooter{3, 1};
  const physics::ProjectileDef def =
      rocket_projectile(rocket, Vec3(1, 2, 3), Vec3(0, 0, -2), shooter, 77);
  EXPECT_EQ(def.position, Vec3(1, 2, 3));
  EXPECT_NEAR(def.velocity.z(), -25, 1e-5);
  EXPECT_NEAR(def.velocity.norm(), 25, 1e-5);
  EXPECT_FLOAT_EQ(def.radius, 0.1f);
  EXPECT_EQ(def.gravity_scale, 0);
  EXPECT_EQ(def.filter.layer, profiles::kLayerProjectile);
  EXPECT_EQ(def.filter.mask,
            profiles::kLayerStatic | profiles::kLayerPlayer | profiles::kLayerProp);
  EXPECT_EQ(def.ignore, shooter);
  EXPECT_EQ(def.user_data, 77u);
}

TEST(Rocket, HitsWallAndReportsHitEvent) {
  physics::World world = combat_world();
  physics::BoxDef wall;
  wall.center = Vec3(0, 2, -10);
  wall.half_extents = Vec3(5, 2, 0.1f);
  ASSERT_TRUE(world.add_box(wall).ok());
  const physics::BodyId shooter = world.create_body(player_body_def(Vec3(0, 0.4f, 0))).value();
  const WeaponConfig& rocket = default_weapon(WeaponKind::RocketLauncher);
  const Vec3 eye(0, 0.65f, 0);
  ASSERT_TRUE(
      world.create_projectile(rocket_projectile(rocket, eye, Vec3(0, 0, -1), shooter, 5)).ok());

  // 9.9 m to the wall's face minus the rocket's radius at 25 m/s: about 0.39 s.
  std::optional<physics::ProjectileHitEvent> hit;
  int steps = 0;
  for (; steps < 60 && !hit; ++steps) {
    ASSERT_TRUE(world.step(kDt).ok());
    if (!world.projectile_hit_events().empty()) hit = world.projectile_hit_events()[0];
  }
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(steps, 24);  // ceil(9.8 / 25 * 60)
  EXPECT_EQ(hit->user_data, 5u);
  EXPECT_FALSE(hit->target.shape.is_null());
  EXPECT_NEAR(hit->point.z(), -9.9, 1e-3);
  EXPECT_NEAR(hit->normal.z(), 1, 1e-4);
  EXPECT_EQ(world.projectile_count(), 0u);
}

TEST(Rocket, NeverHitsShooterButHitsAnotherPlayer) {
  physics::World world = combat_world();
  const physics::BodyId shooter = world.create_body(player_body_def(Vec3(0, 0.4f, 0))).value();
  const physics::BodyId target = world.create_body(player_body_def(Vec3(0, 0.4f, -5))).value();
  const WeaponConfig& rocket = default_weapon(WeaponKind::RocketLauncher);
  ASSERT_TRUE(world
                  .create_projectile(
                      rocket_projectile(rocket, Vec3(0, 0.65f, 0), Vec3(0, 0, -1), shooter, 9))
                  .ok());
  std::optional<physics::ProjectileHitEvent> hit;
  for (int step = 0; step < 60 && !hit; ++step) {
    ASSERT_TRUE(world.step(kDt).ok());
    if (!world.projectile_hit_events().empty()) hit = world.projectile_hit_events()[0];
  }
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->target.body, target);
}

TEST(Grenade, DefinitionIsFastBouncingProjectileLayer) {
  const WeaponConfig& grenade = default_weapon(WeaponKind::GrenadeLauncher);
  const physics::BodyDef def =
      grenade_body(grenade, Vec3(0, 1, 0), Vec3(0, 0, -3), Vec3(1, 0, 0), 11);
  EXPECT_TRUE(def.fast);
  EXPECT_EQ(def.type, physics::BodyType::Dynamic);
  EXPECT_FLOAT_EQ(def.mass, 0.4f);
  EXPECT_FLOAT_EQ(def.radius, 0.15f);
  EXPECT_FLOAT_EQ(def.material.restitution, 0.6f);
  EXPECT_EQ(def.gravity_scale, 1);
  EXPECT_TRUE((def.linear_velocity - Vec3(1, 0, -15)).norm() < 1e-5);
  EXPECT_EQ(def.filter.layer, profiles::kLayerProjectile);
  EXPECT_EQ(def.filter.mask,
            profiles::kLayerStatic | profiles::kLayerPlayer | profiles::kLayerProp);
  EXPECT_EQ(def.user_data, 11u);
}

TEST(Grenade, BouncesOffFloorWithRestitutionAndComesToRest) {
  physics::World world = combat_world();
  const WeaponConfig& grenade = default_weapon(WeaponKind::GrenadeLauncher);
  // Dropped from 3 m with a little forward speed: it hits at about 7.7 m/s.
  const physics::BodyId body =
      world.create_body(grenade_body(grenade, Vec3(0, 3, 0), Vec3(0, 0, -1), Vec3::Zero(), 1))
          .value();
  ASSERT_TRUE(world.set_linear_velocity(body, Vec3(0, 0, -1)).ok());
  Real impact_speed = 0;
  Real rebound_speed = 0;
  Real previous_vy = 0;
  for (int step = 0; step < 120 && rebound_speed == 0; ++step) {
    ASSERT_TRUE(world.step(kDt).ok());
    const Real vy = world.body_state(body).value().linear_velocity.y();
    if (previous_vy < 0 && vy > 0) {
      impact_speed = -previous_vy;
      rebound_speed = vy;
    }
    previous_vy = vy;
  }
  ASSERT_GT(impact_speed, 7);
  EXPECT_NEAR(rebound_speed / impact_speed, 0.6, 0.08);

  // Four seconds later it lies on the floor, still.
  for (int step = 0; step < 240; ++step) ASSERT_TRUE(world.step(kDt).ok());
  const physics::BodyState state = world.body_state(body).value();
  EXPECT_NEAR(state.position.y(), 0.15, 0.01);
  EXPECT_LT(state.linear_velocity.norm(), 0.05);
}

TEST(Grenade, DoesNotBounceInArenaPlayersWithoutRestitution) {
  // Why combat_world_def() exists: the plain profile turns restitution off.
  physics::World world = physics::World::create(profiles::arena_players()).value();
  ASSERT_TRUE(world.add_plane(physics::PlaneDef{}).ok());
  const WeaponConfig& grenade = default_weapon(WeaponKind::GrenadeLauncher);
  const physics::BodyId body =
      world.create_body(grenade_body(grenade, Vec3(0, 3, 0), Vec3(0, -1, 0), Vec3::Zero(), 1))
          .value();
  Real highest_rebound = 0;
  for (int step = 0; step < 120; ++step) {
    ASSERT_TRUE(world.step(kDt).ok());
    highest_rebound = std::max(highest_rebound, world.body_state(body).value().linear_velocity.y());
  }
  EXPECT_LT(highest_rebound, 0.5);
}

TEST(Grenade, LaunchOriginClearsShooterOrIsRefusedAgainstWall) {
  physics::World world = combat_world();
  physics::BoxDef wall;
  wall.center = Vec3(0, 2, -1.2f);
  wall.half_extents = Vec3(5, 2, 0.1f);  // face at z = -1.1
  ASSERT_TRUE(world.add_box(wall).ok());
  const physics::BodyId shooter = world.create_body(player_body_def(Vec3(0, 0.4f, 0))).value();
  const WeaponConfig& grenade = default_weapon(WeaponKind::GrenadeLauncher);
  const Vec3 eye(0, 0.65f, 0);

  // Away from the wall: 0.4 + 0.15 + 0.05 m along the aim, outside the shooter's sphere.
  const std::optional<Vec3> back =
      grenade_launch_origin(world, eye, Vec3(0, 0, 1), shooter, grenade);
  ASSERT_TRUE(back.has_value());
  EXPECT_NEAR(back->z(), 0.6, 1e-5);
  EXPECT_NEAR(back->y(), 0.65, 1e-5);
  // A grenade created there does not touch its shooter.
  const physics::BodyId body =
      world.create_body(grenade_body(grenade, *back, Vec3(0, 0, 1), Vec3::Zero(), 1)).value();
  EXPECT_TRUE(world.is_valid(body));
  for (int step = 0; step < 3; ++step) ASSERT_TRUE(world.step(kDt).ok());
  EXPECT_LT(world.body_state(shooter).value().linear_velocity.norm(), 0.2);

  // Facing the wall 1.1 m away there is room (0.6 + 0.15 < 1.1); facing it closer there is not.
  EXPECT_TRUE(grenade_launch_origin(world, eye, Vec3(0, 0, -1), shooter, grenade).has_value());
  const Vec3 close_eye(0, 0.65f, -0.55f);
  EXPECT_FALSE(grenade_launch_origin(world, close_eye, Vec3(0, 0, -1), {}, grenade).has_value());
  EXPECT_FALSE(grenade_launch_origin(world, eye, Vec3::Zero(), shooter, grenade).has_value());
}

}  // namespace
}  // namespace ricochet::server::weapons_test
