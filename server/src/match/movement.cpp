/// The match's inputs as character intents (movement.h).

#include "ricochet/server/movement.h"

namespace ricochet::server {

std::string MovementConfig::validate() const {
  std::string error = physics::CharacterMotionConfig::validate();
  return error.empty() ? error : "movement " + error;
}

physics::Vec3 wish_direction(const PlayerInput& input) {
  return physics::yaw_wish_direction(input.yaw_rad, input.move_right, input.move_forward);
}

physics::CharacterIntent character_intent(const PlayerInput& input) {
  return {wish_direction(input),
          physics::stick_speed_fraction(input.move_right, input.move_forward),
          input.pressed(proto::kButtonJump)};
}

physics::Vec3 move_velocity(const MovementConfig& config, const PlayerInput& input,
                            const physics::Vec3& velocity_mps, bool grounded, float dt_s) {
  return physics::character_velocity(config, character_intent(input), velocity_mps, grounded, dt_s);
}

}  // namespace ricochet::server
