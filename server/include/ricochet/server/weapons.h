#pragma once
/// Weapons: their configuration and the physics objects they shoot.
///
/// Three weapons: a hitscan rifle (a ray, cast by lag_compensation.h), a rocket launcher (a swept
/// physics projectile that explodes on contact) and a grenade launcher (a `fast` rigid body that
/// bounces and explodes when its fuse runs out). What an explosion does is combat.h.
///
/// Grenades bounce only in a world with restitution on: profiles::arena_players() turns it off,
/// combat_world_def() is that profile with it on (players have restitution 0, so only grenades
/// bounce).

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ricochet/physics/body.h"
#include "ricochet/physics/projectile.h"
#include "ricochet/physics/types.h"
#include "ricochet/physics/world.h"
#include "ricochet/physics/world_def.h"
#include "ricochet/proto/weapon_wire.h"
#include "ricochet/wire/game.pb.h"

namespace ricochet::server {

enum class WeaponKind : std::uint8_t { Rifle = 0, RocketLauncher = 1, GrenadeLauncher = 2 };
/// One per wire::Weapon: kind = wire::Weapon - 1 (proto/weapon_wire.h has the slots).
inline constexpr std::size_t kWeaponCount = proto::kWeaponCount;
static_assert(kWeaponCount == static_cast<std::size_t>(WeaponKind::GrenadeLauncher) + 1);
/// "rifle", "rocket_launcher", "grenade_launcher".
const char* name(WeaponKind kind);
/// The wire's Weapon of `kind`.
wire::Weapon to_wire(WeaponKind kind);
/// The weapon a slot selects (proto::weapon_of_slot); nothing for 0 (keep the weapon) or a slot
/// without a weapon.
std::optional<WeaponKind> weapon_for_slot(std::uint32_t slot);

/// One weapon; default_weapons() has the shipped values.
struct WeaponConfig {
  float fire_interval_s = 0;  ///< s between shots, 0.01..10
  int damage = 0;             ///< rifle: per hit; projectiles: at the explosion's centre; 0..1000
  float range_m = 0;          ///< rifle: ray length, 1..10000 (unused by projectiles)
  float spread_rad = 0;       ///< rifle: half-angle of a uniform cone (0 = exact), 0..0.5 rad
  int ammo_start = 0;         ///< rounds at spawn, 0..ammo_max
  int ammo_max = 0;           ///< 1..10000
  int ammo_per_pickup = 0;    ///< rounds an ammo pickup gives, 0..ammo_max
  float projectile_speed_mps = 0;  ///< 0..1000 m/s (a grenade adds the shooter's velocity)
  float projectile_radius_m = 0;   ///< 0..1 m (a rocket of 0 is a ray; a grenade needs >= 0.01)
  float gravity_scale = 0;         ///< multiplies the world's gravity, 0..10
  float restitution = 0;           ///< grenade bounce, 0..1
  float fuse_s = 0;                ///< grenade: explodes after this; rocket: max flight; 0..60 s
  float explosion_radius_m = 0;    ///< 0..50 m (0: no explosion)
  float explosion_impulse_ns = 0;  ///< N·s at the centre, falls off like the damage; 0..100000

  /// Empty when valid; otherwise "<name> <field> must be <range>, got <value>".
  std::string validate(const char* name) const;
};

/// The shipped weapons, by kind:
///   rifle   0.1 s, 20 per hit, 200 m, no spread, ammo 100/200/50
///   rocket  0.8 s, 100 at the centre, 25 m/s, r 0.1 m, no gravity, 5 s flight, 3.5 m, 600 N·s,
///           ammo 10/50/5
///   grenade 0.6 s, 100 at the centre, 15 m/s, r 0.15 m, gravity 1, restitution 0.6, 2 s fuse,
///           3.5 m, 500 N·s, ammo 10/50/5
std::array<WeaponConfig, kWeaponCount> default_weapons();

struct WeaponsConfig {
  std::array<WeaponConfig, kWeaponCount> weapons = default_weapons();  ///< by WeaponKind
  float self_damage_scale = 0.5f;    ///< 0..1, damage of one's own explosions
  bool friendly_fire = false;        ///< team deathmatch: teammates take damage
  float friendly_fire_scale = 0.5f;  ///< 0..1, of the damage, when friendly_fire
  float armor_absorb = 0.66f;        ///< 0..1, fraction of damage armour takes while it lasts
  float max_turn_rate_rad_s = 60;    ///< 1..10000, the aim check (combat.h turn_rate_ok)

  const WeaponConfig& operator[](WeaponKind kind) const {
    return weapons[static_cast<std::size_t>(kind)];
  }
  /// Each weapon's validate(), then what projectile weapons need: a speed >= 1 m/s and a fuse
  /// >= 0.05 s, and the grenade a radius >= 0.01 m.
  std::string validate() const;
};

/// profiles::arena_players() with restitution on, so grenades bounce.
physics::WorldDef combat_world_def();

/// What the join reply tells a client of each weapon (WeaponSpec, rifle first): the rifle is
/// hitscan (speed 0, no gravity, its range); a rocket or grenade flies at its speed under
/// combat_world_def()'s gravity times its gravity scale (range 0).
std::vector<wire::WeaponSpec> weapon_specs(const WeaponsConfig& weapons);

/// A rocket from `origin` (the shooter's eye) along `direction` (normalised here) at the
/// weapon's speed; it hits statics, players and props (not other projectiles), never `shooter`.
/// The match removes it after fuse_s of flight.
physics::ProjectileDef rocket_projectile(const WeaponConfig& weapon, const physics::Vec3& origin,
                                         const physics::Vec3& direction, physics::BodyId shooter,
                                         std::uint64_t user_data);

/// Where a grenade leaves the shooter's sphere: `eye` moved along `direction` until the grenade
/// clears the shooter (player radius + grenade radius + 5 cm), by a sphere cast against statics,
/// players and props. Nothing when something is in the way before that point: the grenade has
/// no room and the match explodes it at `eye` at once.
std::optional<physics::Vec3> grenade_launch_origin(const physics::World& world,
                                                   const physics::Vec3& eye,
                                                   const physics::Vec3& direction,
                                                   physics::BodyId shooter,
                                                   const WeaponConfig& weapon);

/// A grenade at `origin` (from grenade_launch_origin) moving at the weapon's speed along
/// `direction` plus the shooter's velocity: a 0.4 kg `fast` sphere with the weapon's restitution,
/// layer kLayerProjectile, colliding with statics, players and props (not other grenades).
physics::BodyDef grenade_body(const WeaponConfig& weapon, const physics::Vec3& origin,
                              const physics::Vec3& direction, const physics::Vec3& shooter_velocity,
                              std::uint64_t user_data);

}  // namespace ricochet::server
