/// Ground and air movement, jumping and the ground test (movement.h).

#include "ricochet/server/movement.h"

#include "range_check.h"

#include <cmath>
#include <numbers>

#include "ricochet/physics/scene_profile.h"

namespace ricochet::server {

namespace {

using physics::Real;
using physics::Vec3;

/// Adds speed along `direction` until the speed along it reaches `wish_speed`, at most
/// acceleration * wish_speed * dt (Quake's PM_Accelerate).
Vec3 accelerate(const Vec3& velocity, const Vec3& direction, float wish_speed, float acceleration,
                float dt_s) {
  const Real along = velocity.dot(direction);
  const Real missing = Real(wish_speed) - along;
  if (missing <= 0) return velocity;
  const Real gain = std::min(Real(acceleration * wish_speed * dt_s), missing);
  return velocity + gain * direction;
}

/// Slows the horizontal velocity (Quake's PM_Friction).
Vec3 apply_friction(const Vec3& velocity, const MovementConfig& config, float dt_s) {
  const Real speed = std::hypot(velocity.x(), velocity.z());
  if (speed <= 0) return velocity;
  const Real drop = std::max(speed, Real(config.stop_speed_mps)) * config.friction * dt_s;
  const Real scale = std::max(speed - drop, Real(0)) / speed;
  return Vec3(velocity.x() * scale, velocity.y(), velocity.z() * scale);
}

}  // namespace

std::string MovementConfig::validate() const {
  if (!within(max_speed_mps, 0.1f, 100))
    return range_error("movement", "max_speed_mps", "0.1..100", max_speed_mps);
  if (!within(ground_acceleration, 0, 1000)) {
    return range_error("movement", "ground_acceleration", "0..1000", ground_acceleration);
  }
  if (!within(air_acceleration, 0, 1000)) {
    return range_error("movement", "air_acceleration", "0..1000", air_acceleration);
  }
  if (!within(friction, 0, 1000)) return range_error("movement", "friction", "0..1000", friction);
  if (!within(stop_speed_mps, 0, 100))
    return range_error("movement", "stop_speed_mps", "0..100", stop_speed_mps);
  if (!within(jump_speed_mps, 0, 100))
    return range_error("movement", "jump_speed_mps", "0..100", jump_speed_mps);
  if (!within(ground_max_slope_deg, 0, 89)) {
    return range_error("movement", "ground_max_slope_deg", "0..89", ground_max_slope_deg);
  }
  if (!within(ground_probe_m, 0.001f, 1)) {
    return range_error("movement", "ground_probe_m", "0.001..1", ground_probe_m);
  }
  return {};
}

physics::BodyDef player_body_def(const Vec3& position) {
  physics::BodyDef def = physics::profiles::player(position);
  def.material.friction = 0;
  return def;
}

bool is_grounded(const physics::World& world, physics::BodyId player, Real radius_m,
                 const MovementConfig& config) {
  const physics::Result<physics::BodyState> state = world.body_state(player);
  if (!state.ok()) return false;
  // A slightly smaller sphere swept down from the centre: it starts clear of the resting
  // contact (which the solver leaves up to the linear slop deep) and touches what is below.
  const Real inset = std::min(Real(0.02), radius_m / 2);
  physics::QueryFilter filter;
  filter.mask = physics::profiles::kLayerStatic | physics::profiles::kLayerPlayer |
                physics::profiles::kLayerProp;
  filter.ignore = player;
  physics::RayHit hit;
  if (!world.sphere_cast(state.value().position, radius_m - inset, Vec3(0, -1, 0),
                         inset + Real(config.ground_probe_m), filter, hit)) {
    return false;
  }
  const Real min_normal_y =
      std::cos(Real(config.ground_max_slope_deg) * std::numbers::pi_v<Real> / 180);
  return hit.normal.y() >= min_normal_y;
}

Vec3 wish_direction(const PlayerInput& input) {
  // Yaw turns counter-clockwise about +Y; yaw 0 looks along -Z with +X on the right.
  const Real sin_yaw = std::sin(Real(input.yaw_rad));
  const Real cos_yaw = std::cos(Real(input.yaw_rad));
  const Vec3 forward(-sin_yaw, 0, -cos_yaw);
  const Vec3 right(cos_yaw, 0, -sin_yaw);
  const Vec3 wish = forward * Real(input.move_forward) + right * Real(input.move_right);
  const Real length = wish.norm();
  return length > Real(1e-6) ? Vec3(wish / length) : Vec3::Zero();
}

Vec3 move_velocity(const MovementConfig& config, const PlayerInput& input, const Vec3& velocity_mps,
                   bool grounded, float dt_s) {
  const Vec3 direction = wish_direction(input);
  // Input length (<= 1) scales the wished speed: half a stick is half speed.
  const float amount = std::min(1.0f, std::hypot(input.move_right, input.move_forward));
  const float wish_speed = config.max_speed_mps * amount;
  Vec3 velocity = velocity_mps;
  if (grounded) {
    velocity = apply_friction(velocity, config, dt_s);
    velocity = accelerate(velocity, direction, wish_speed, config.ground_acceleration, dt_s);
    if (input.pressed(kButtonJump) && velocity.y() < config.jump_speed_mps) {
      velocity.y() = config.jump_speed_mps;
    }
  } else {
    velocity = accelerate(velocity, direction, wish_speed, config.air_acceleration, dt_s);
  }
  return velocity;
}

}  // namespace ricochet::server
