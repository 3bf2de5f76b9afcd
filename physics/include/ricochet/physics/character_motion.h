#pragma once
/// A walking character on the physics core: a sphere whose velocity is decided each step from
/// what its owner wishes (a direction, a fraction of full speed, a jump), while gravity and the
/// contacts stay the world's. The model is Quake's (PM_Friction, PM_Accelerate): friction on
/// the ground, then acceleration towards the wished direction until the speed along it reaches
/// the wished speed, weaker in the air (air control), and a jump only when grounded.
///
/// Per step, before World::step(dt):
///   grounded = is_grounded(world, body, radius, config)
///   set_linear_velocity(body, character_velocity(config, intent, velocity, grounded, dt))
///
/// The character's body is character_body_def(): frictionless, so the only friction is the
/// model's and the speeds below are the speeds the character gets. Game-agnostic (like Jolt's
/// CharacterVirtual): a server and a client predicting it run the same code on the same numbers.

#include <string>

#include "ricochet/physics/body.h"
#include "ricochet/physics/types.h"
#include "ricochet/physics/world.h"

namespace ricochet::physics {

struct CharacterMotionConfig {
  float max_speed_mps = 7;          ///< wished speed at full input, on the ground and in the air
  float ground_acceleration = 10;   ///< 1/s: speed gained per second = this * max_speed
  float air_acceleration = 1;       ///< 1/s: the same in the air (air control)
  float friction = 6;               ///< 1/s, on the ground only
  float stop_speed_mps = 2;         ///< below this, friction acts as if at this speed (stops)
  float jump_speed_mps = 5;         ///< vertical speed a jump sets: height v²/2g (1.27 m at 9.81)
  float ground_max_slope_deg = 50;  ///< steeper surfaces are walls, not ground
  float ground_probe_m = 0.05f;     ///< how far below the sphere ground still counts

  /// Empty when valid; otherwise "<field> must be <range>, got <value>".
  std::string validate() const;
};

/// What the character's owner wishes for one step.
struct CharacterIntent {
  Vec3 wish_direction = Vec3::Zero();  ///< unit and horizontal, or zero (no move)
  float wish_speed_fraction = 0;       ///< 0..1 of max_speed_mps
  bool jump = false;                   ///< held: jump when grounded
};

/// The body of a character at `position`: profiles::player() (0.4 m radius, 80 kg, no spin)
/// with a frictionless material.
BodyDef character_body_def(const Vec3& position);

/// Whether the character's sphere stands on something (a static surface, a player, a prop) no
/// steeper than ground_max_slope_deg within ground_probe_m below it.
bool is_grounded(const World& world, BodyId character, Real radius_m,
                 const CharacterMotionConfig& config);

/// The velocity for the next step from the current one. `dt_s` is the fixed step, s.
Vec3 character_velocity(const CharacterMotionConfig& config, const CharacterIntent& intent,
                        const Vec3& velocity_mps, bool grounded, float dt_s);

/// The unit horizontal direction of a stick (`right`, `forward`, each -1..1) seen from yaw
/// `yaw_rad` (counter-clockwise about +Y; yaw 0 looks along -Z with +X on the right); zero when
/// the stick is centred.
Vec3 yaw_wish_direction(float yaw_rad, float right, float forward);

/// The wished speed fraction of a stick: its length, at most 1 (half a stick is half speed).
float stick_speed_fraction(float right, float forward);

}  // namespace ricochet::physics
