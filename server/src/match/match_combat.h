#pragma once
/// The state of a match's weapons (weapons.h, combat.h, lag_compensation.h): the rockets and
/// grenades in flight, the lag compensation ring of the players' past positions, and the
/// explosions' scratch. The phases that change it are in match_game.h.

#include <cstdint>
#include <vector>

#include "ricochet/physics/world.h"
#include "ricochet/server/combat.h"
#include "ricochet/server/lag_compensation.h"
#include "ricochet/server/rules.h"
#include "ricochet/server/weapons.h"

namespace ricochet::server {

/// A rocket or grenade in flight.
struct Projectile {
  std::uint32_t entity_id = 0;
  WeaponKind weapon = WeaponKind::RocketLauncher;
  std::uint32_t owner_entity = 0;
  Team owner_team = Team::None;
  physics::ProjectileId rocket;    ///< a rocket's
  physics::BodyId grenade;         ///< a grenade's
  std::uint32_t expires_tick = 0;  ///< fuse (grenade) or longest flight (rocket)
  physics::Vec3 position_m = physics::Vec3::Zero();
  physics::Vec3 velocity_mps = physics::Vec3::Zero();
};

struct Combat {
  Combat(const LagCompensationConfig& lag_config, int tick_rate_hz)
      : lag(lag_config, tick_rate_hz) {}

  std::vector<Projectile> projectiles;  ///< sorted by entity id
  LagCompensation lag;
  std::vector<LagSample> lag_samples;  ///< scratch: this step's players for `lag`
  // An explosion's scratch.
  std::vector<ExplosionTarget> explosion_targets;
  std::vector<ExplosionEffect> explosion_effects;
  std::vector<std::uint32_t> explosion_entities;  ///< entity of each explosion target (0: none)
};

}  // namespace ricochet::server
