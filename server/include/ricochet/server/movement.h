#pragma once
/// Player movement: the match's inputs on the physics core's character motion
/// (ricochet/physics/character_motion.h, which holds the model, the ground test and the player's
/// body). This adapter turns a PlayerInput into the character's intent and names the config as
/// the match's ("movement ..." in errors and config keys). Clients predicting their player run
/// the same physics code with the numbers of the join reply (PROTOCOL.md Movement rules).

#include <string>

#include "ricochet/physics/character_motion.h"
#include "ricochet/physics/types.h"
#include "ricochet/physics/world.h"
#include "ricochet/server/input_buffer.h"

namespace ricochet::server {

/// The character motion's numbers, validated as the match's "movement" section.
struct MovementConfig : physics::CharacterMotionConfig {
  /// Empty when valid; otherwise "movement <field> must be <range>, got <value>".
  std::string validate() const;
};

/// The physics body of a player at `position`: physics::character_body_def().
inline physics::BodyDef player_body_def(const physics::Vec3& position) {
  return physics::character_body_def(position);
}

/// What the input asks of the player's character: the stick's direction under the yaw, its
/// length as the speed fraction, and the jump button.
physics::CharacterIntent character_intent(const PlayerInput& input);

/// The velocity for the next step from the current one. `dt_s` is the fixed step.
physics::Vec3 move_velocity(const MovementConfig& config, const PlayerInput& input,
                            const physics::Vec3& velocity_mps, bool grounded, float dt_s);

/// Unit horizontal direction the input wishes to move in (zero when no move input).
physics::Vec3 wish_direction(const PlayerInput& input);

using physics::is_grounded;

}  // namespace ricochet::server
