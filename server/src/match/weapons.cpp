/// Weapon configuration, its validation, and the rockets and grenades they launch (weapons.h).

#include "ricochet/server/weapons.h"

#include <cmath>

#include "range_check.h"
#include "ricochet/physics/scene_profile.h"
#include "ricochet/server/movement.h"

namespace ricochet::server {

namespace {

using physics::Real;
using physics::Vec3;
namespace profiles = physics::profiles;

/// What rockets and grenades collide with: the arena, players and props, not each other.
constexpr std::uint32_t kProjectileMask =
    profiles::kLayerStatic | profiles::kLayerPlayer | profiles::kLayerProp;
constexpr Real kGrenadeMassKg = Real(0.4);
/// Gap between the shooter's sphere and a grenade leaving it, m.
constexpr Real kLaunchClearanceM = Real(0.05);

Vec3 unit_or_zero(const Vec3& direction) {
  const Real length = direction.norm();
  return std::isfinite(length) && length > 0 ? Vec3(direction / length) : Vec3(Vec3::Zero());
}

}  // namespace

const char* name(WeaponKind kind) {
  switch (kind) {
    case WeaponKind::Rifle:
      return "rifle";
    case WeaponKind::RocketLauncher:
      return "rocket_launcher";
    case WeaponKind::GrenadeLauncher:
      return "grenade_launcher";
  }
  return "unknown";
}

wire::Weapon to_wire(WeaponKind kind) {
  return static_cast<wire::Weapon>(static_cast<int>(kind) + 1);
}

std::optional<WeaponKind> weapon_for_slot(std::uint32_t slot) {
  const std::optional<wire::Weapon> weapon = proto::weapon_of_slot(slot);
  if (!weapon) return std::nullopt;
  return static_cast<WeaponKind>(static_cast<int>(*weapon) - 1);
}

std::string WeaponConfig::validate(const char* name) const {
  if (!within(fire_interval_s, 0.01, 10))
    return range_error(name, "fire_interval_s", "0.01..10", fire_interval_s);
  if (!within(damage, 0, 1000)) return range_error(name, "damage", "0..1000", damage);
  if (!within(range_m, 1, 10000)) return range_error(name, "range_m", "1..10000", range_m);
  if (!within(spread_rad, 0, 0.5)) return range_error(name, "spread_rad", "0..0.5", spread_rad);
  if (!within(ammo_max, 1, 10000)) return range_error(name, "ammo_max", "1..10000", ammo_max);
  if (!within(ammo_start, 0, ammo_max))
    return range_error(name, "ammo_start", "0..ammo_max", ammo_start);
  if (!within(ammo_per_pickup, 0, ammo_max))
    return range_error(name, "ammo_per_pickup", "0..ammo_max", ammo_per_pickup);
  if (!within(projectile_speed_mps, 0, 1000))
    return range_error(name, "projectile_speed_mps", "0..1000", projectile_speed_mps);
  if (!within(projectile_radius_m, 0, 1))
    return range_error(name, "projectile_radius_m", "0..1", projectile_radius_m);
  if (!within(gravity_scale, 0, 10))
    return range_error(name, "gravity_scale", "0..10", gravity_scale);
  if (!within(restitution, 0, 1)) return range_error(name, "restitution", "0..1", restitution);
  if (!within(fuse_s, 0, 60)) return range_error(name, "fuse_s", "0..60", fuse_s);
  if (!within(explosion_radius_m, 0, 50))
    return range_error(name, "explosion_radius_m", "0..50", explosion_radius_m);
  if (!within(explosion_impulse_ns, 0, 100000))
    return range_error(name, "explosion_impulse_ns", "0..100000", explosion_impulse_ns);
  return {};
}

std::array<WeaponConfig, kWeaponCount> default_weapons() {
  const WeaponConfig rifle{.fire_interval_s = 0.1f,
                           .damage = 20,
                           .range_m = 200,
                           .spread_rad = 0,
                           .ammo_start = 100,
                           .ammo_max = 200,
                           .ammo_per_pickup = 50,
                           .projectile_speed_mps = 0,
                           .projectile_radius_m = 0,
                           .gravity_scale = 0,
                           .restitution = 0,
                           .fuse_s = 0,
                           .explosion_radius_m = 0,
                           .explosion_impulse_ns = 0};
  const WeaponConfig rocket{.fire_interval_s = 0.8f,
                            .damage = 100,
                            .range_m = 200,
                            .spread_rad = 0,
                            .ammo_start = 10,
                            .ammo_max = 50,
                            .ammo_per_pickup = 5,
                            .projectile_speed_mps = 25,
                            .projectile_radius_m = 0.1f,
                            .gravity_scale = 0,
                            .restitution = 0,
                            .fuse_s = 5,
                            .explosion_radius_m = 3.5f,
                            .explosion_impulse_ns = 600};
  const WeaponConfig grenade{.fire_interval_s = 0.6f,
                             .damage = 100,
                             .range_m = 200,
                             .spread_rad = 0,
                             .ammo_start = 10,
                             .ammo_max = 50,
                             .ammo_per_pickup = 5,
                             .projectile_speed_mps = 15,
                             .projectile_radius_m = 0.15f,
                             .gravity_scale = 1,
                             .restitution = 0.6f,
                             .fuse_s = 2,
                             .explosion_radius_m = 3.5f,
                             .explosion_impulse_ns = 500};
  return {rifle, rocket, grenade};
}

std::string WeaponsConfig::validate() const {
  for (std::size_t i = 0; i < kWeaponCount; ++i) {
    const char* weapon = name(static_cast<WeaponKind>(i));
    if (std::string error = weapons[i].validate(weapon); !error.empty()) return error;
  }
  for (WeaponKind kind : {WeaponKind::RocketLauncher, WeaponKind::GrenadeLauncher}) {
    const WeaponConfig& w = (*this)[kind];
    if (w.projectile_speed_mps < 1)
      return range_error(name(kind), "projectile_speed_mps", "1..1000", w.projectile_speed_mps);
    if (w.fuse_s < 0.05f) return range_error(name(kind), "fuse_s", "0.05..60", w.fuse_s);
  }
  const WeaponConfig& grenade = (*this)[WeaponKind::GrenadeLauncher];
  if (grenade.projectile_radius_m < 0.01f) {
    return range_error(name(WeaponKind::GrenadeLauncher), "projectile_radius_m", "0.01..1",
                       grenade.projectile_radius_m);
  }
  if (!within(self_damage_scale, 0, 1))
    return range_error("weapons", "self_damage_scale", "0..1", self_damage_scale);
  if (!within(friendly_fire_scale, 0, 1))
    return range_error("weapons", "friendly_fire_scale", "0..1", friendly_fire_scale);
  if (!within(armor_absorb, 0, 1))
    return range_error("weapons", "armor_absorb", "0..1", armor_absorb);
  if (!within(max_turn_rate_rad_s, 1, 10000))
    return range_error("weapons", "max_turn_rate_rad_s", "1..10000", max_turn_rate_rad_s);
  return {};
}

physics::WorldDef combat_world_def() {
  physics::WorldDef def = profiles::arena_players();
  def.enable_restitution = true;
  return def;
}

std::vector<wire::WeaponSpec> weapon_specs(const WeaponsConfig& weapons) {
  const Vec3 gravity = combat_world_def().gravity;
  std::vector<wire::WeaponSpec> specs(kWeaponCount);
  for (std::size_t k = 0; k < kWeaponCount; ++k) {
    const auto kind = static_cast<WeaponKind>(k);
    const WeaponConfig& weapon = weapons[kind];
    wire::WeaponSpec& spec = specs[k];
    spec.set_weapon(to_wire(kind));
    spec.set_fire_interval_s(weapon.fire_interval_s);
    const bool hitscan = kind == WeaponKind::Rifle;
    spec.set_range_m(hitscan ? weapon.range_m : 0);
    spec.set_projectile_speed_mps(hitscan ? 0 : weapon.projectile_speed_mps);
    const Real gravity_scale = hitscan ? Real(0) : Real(weapon.gravity_scale);
    for (int axis = 0; axis < 3; ++axis) {
      const auto g = static_cast<float>(gravity[axis] * gravity_scale);
      spec.add_gravity_mps2(g == 0 ? 0.0f : g);  // no -0 for a scale of 0
    }
    spec.set_explosion_radius_m(hitscan ? 0 : weapon.explosion_radius_m);
  }
  return specs;
}

physics::ProjectileDef rocket_projectile(const WeaponConfig& weapon, const Vec3& origin,
                                         const Vec3& direction, physics::BodyId shooter,
                                         std::uint64_t user_data) {
  physics::ProjectileDef def;
  def.position = origin;
  def.velocity = unit_or_zero(direction) * Real(weapon.projectile_speed_mps);
  def.radius = Real(weapon.projectile_radius_m);
  def.gravity_scale = Real(weapon.gravity_scale);
  def.filter = {profiles::kLayerProjectile, kProjectileMask};
  def.ignore = shooter;
  def.user_data = user_data;
  return def;
}

std::optional<Vec3> grenade_launch_origin(const physics::World& world, const Vec3& eye,
                                          const Vec3& direction, physics::BodyId shooter,
                                          const WeaponConfig& weapon) {
  const Vec3 unit = unit_or_zero(direction);
  if (unit.isZero()) return std::nullopt;
  const Real radius = Real(weapon.projectile_radius_m);
  const Real player_radius = player_body_def(Vec3::Zero()).radius;
  // From the eye (inside the shooter) to where the grenade's sphere clears the shooter's.
  const Real distance = player_radius + radius + kLaunchClearanceM;
  physics::QueryFilter filter;
  filter.mask = kProjectileMask;
  filter.ignore = shooter;
  physics::RayHit hit;
  if (world.sphere_cast(eye, radius, unit, distance, filter, hit)) return std::nullopt;
  return Vec3(eye + unit * distance);
}

physics::BodyDef grenade_body(const WeaponConfig& weapon, const Vec3& origin, const Vec3& direction,
                              const Vec3& shooter_velocity, std::uint64_t user_data) {
  physics::BodyDef def;
  def.position = origin;
  def.linear_velocity =
      unit_or_zero(direction) * Real(weapon.projectile_speed_mps) + shooter_velocity;
  def.radius = Real(weapon.projectile_radius_m);
  def.mass = kGrenadeMassKg;
  def.material.restitution = Real(weapon.restitution);
  def.gravity_scale = Real(weapon.gravity_scale);
  def.lock_rotation = true;
  def.fast = true;
  def.allow_sleep = false;
  def.filter = {profiles::kLayerProjectile, kProjectileMask};
  def.user_data = user_data;
  return def;
}

}  // namespace ricochet::server
