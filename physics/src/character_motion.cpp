/// Ground and air motion, jumping and the ground test of a character (character_motion.h).

#include "ricochet/physics/character_motion.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "ricochet/physics/scene_profile.h"

namespace ricochet::physics {

namespace {

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
Vec3 apply_friction(const Vec3& velocity, const CharacterMotionConfig& config, float dt_s) {
  const Real speed = std::hypot(velocity.x(), velocity.z());
  if (speed <= 0) return velocity;
  const Real drop = std::max(speed, Real(config.stop_speed_mps)) * config.friction * dt_s;
  const Real scale = std::max(speed - drop, Real(0)) / speed;
  return Vec3(velocity.x() * scale, velocity.y(), velocity.z() * scale);
}

bool within(float value, float low, float high) {
  return std::isfinite(value) && value >= low && value <= high;
}

std::string range_error(const char* field, const char* range, float value) {
  return std::string(field) + " must be " + range + ", got " + std::to_string(value);
}

}  // namespace

std::string CharacterMotionConfig::validate() const {
  if (!within(max_speed_mps, 0.1f, 100))
    return range_error("max_speed_mps", "0.1..100", max_speed_mps);
  if (!within(ground_acceleration, 0, 1000))
    return range_error("ground_acceleration", "0..1000", ground_acceleration);
  if (!within(air_acceleration, 0, 1000))
    return range_error("air_acceleration", "0..1000", air_acceleration);
  if (!within(friction, 0, 1000)) return range_error("friction", "0..1000", friction);
  if (!within(stop_speed_mps, 0, 100))
    return range_error("stop_speed_mps", "0..100", stop_speed_mps);
  if (!within(jump_speed_mps, 0, 100))
    return range_error("jump_speed_mps", "0..100", jump_speed_mps);
  if (!within(ground_max_slope_deg, 0, 89))
    return range_error("ground_max_slope_deg", "0..89", ground_max_slope_deg);
  if (!within(ground_probe_m, 0.001f, 1))
    return range_error("ground_probe_m", "0.001..1", ground_probe_m);
  return {};
}

BodyDef character_body_def(const Vec3& position) {
  BodyDef def = profiles::player(position);
  def.material.friction = 0;
  return def;
}

bool is_grounded(const World& world, BodyId character, Real radius_m,
                 const CharacterMotionConfig& config) {
  const Result<BodyState> state = world.body_state(character);
  if (!state.ok()) return false;
  // A slightly smaller sphere swept down from the centre: it starts clear of the resting
  // contact (which the solver leaves up to the linear slop deep) and touches what is below.
  const Real inset = std::min(Real(0.02), radius_m / 2);
  QueryFilter filter;
  filter.mask = profiles::kLayerStatic | profiles::kLayerPlayer | profiles::kLayerProp;
  filter.ignore = character;
  RayHit hit;
  if (!world.sphere_cast(state.value().position, radius_m - inset, Vec3(0, -1, 0),
                         inset + Real(config.ground_probe_m), filter, hit)) {
    return false;
  }
  const Real min_normal_y =
      std::cos(Real(config.ground_max_slope_deg) * std::numbers::pi_v<Real> / 180);
  return hit.normal.y() >= min_normal_y;
}

Vec3 yaw_wish_direction(float yaw_rad, float right, float forward) {
  const Real sin_yaw = std::sin(Real(yaw_rad));
  const Real cos_yaw = std::cos(Real(yaw_rad));
  const Vec3 ahead(-sin_yaw, 0, -cos_yaw);
  const Vec3 side(cos_yaw, 0, -sin_yaw);
  const Vec3 wish = ahead * Real(forward) + side * Real(right);
  const Real length = wish.norm();
  return length > Real(1e-6) ? Vec3(wish / length) : Vec3::Zero();
}

float stick_speed_fraction(float right, float forward) {
  return std::min(1.0f, std::hypot(right, forward));
}

Vec3 character_velocity(const CharacterMotionConfig& config, const CharacterIntent& intent,
                        const Vec3& velocity_mps, bool grounded, float dt_s) {
  const float wish_speed = config.max_speed_mps * intent.wish_speed_fraction;
  Vec3 velocity = velocity_mps;
  if (grounded) {
    velocity = apply_friction(velocity, config, dt_s);
    velocity =
        accelerate(velocity, intent.wish_direction, wish_speed, config.ground_acceleration, dt_s);
    if (intent.jump && velocity.y() < config.jump_speed_mps) velocity.y() = config.jump_speed_mps;
  } else {
    velocity =
        accelerate(velocity, intent.wish_direction, wish_speed, config.air_acceleration, dt_s);
  }
  return velocity;
}

}  // namespace ricochet::physics
