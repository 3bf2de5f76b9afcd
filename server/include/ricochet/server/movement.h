#pragma once
/// Player movement on the physics core (arena_players profile): the input decides the velocity
/// a player wants, the world's contacts and gravity do the rest.
///
/// Per tick, before the physics step: friction on the ground, then acceleration towards the
/// wished direction (Quake style: accelerate until the speed along the wished direction reaches
/// the wished speed), weaker in the air (air control), and a jump only when grounded. Gravity is
/// the world's. Players have frictionless surfaces in the physics (player_body_def()), so the
/// only friction is this one and the speeds below are the speeds players get.

#include <string>

#include "ricochet/physics/types.h"
#include "ricochet/physics/world.h"
#include "ricochet/server/input_buffer.h"

namespace ricochet::server {

struct MovementConfig {
  float max_speed_mps = 7;          ///< wished speed at full input, on the ground and in the air
  float ground_acceleration = 10;   ///< 1/s: speed gained per second = this * max_speed
  float air_acceleration = 1;       ///< 1/s: the same in the air (air control)
  float friction = 6;               ///< 1/s, on the ground only
  float stop_speed_mps = 2;         ///< below this, friction acts as if at this speed (stops)
  float jump_speed_mps = 5;         ///< vertical speed a jump sets: height v²/2g (1.27 m at 9.81)
  float ground_max_slope_deg = 50;  ///< steeper surfaces are walls, not ground
  float ground_probe_m = 0.05f;     ///< how far below the sphere ground still counts

  std::string validate() const;
};

/// The physics body of a player at `position`: profiles::player() with a frictionless material.
physics::BodyDef player_body_def(const physics::Vec3& position);

/// Whether the player's sphere stands on something (a static surface, another player, a prop)
/// no steeper than ground_max_slope_deg within ground_probe_m below it.
bool is_grounded(const physics::World& world, physics::BodyId player, physics::Real radius_m,
                 const MovementConfig& config);

/// The velocity for the next step from the current one. `dt_s` is the fixed step.
physics::Vec3 move_velocity(const MovementConfig& config, const PlayerInput& input,
                            const physics::Vec3& velocity_mps, bool grounded, float dt_s);

/// Unit horizontal direction the input wishes to move in (zero when no move input).
physics::Vec3 wish_direction(const PlayerInput& input);

}  // namespace ricochet::server
