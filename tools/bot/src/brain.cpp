#include "ricochet/bot/brain.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "ricochet/proto/input_wire.h"

namespace ricochet::bot {
namespace {

constexpr double kAimRedrawS = 0.25;     ///< s between two draws of the aim error
constexpr double kPreferenceS = 4.0;     ///< s between two draws of the preferred weapon
constexpr double kWaypointS = 6.0;       ///< s at most towards one waypoint
constexpr double kProgressCheckS = 1.0;  ///< s between two stuck checks
constexpr float kStuckM = 0.3f;          ///< m moved within a check below which the bot is stuck
constexpr float kWaypointReachedM = 1.0f;
constexpr float kFightFarM = 12.0f;   ///< closer than this the bot stops closing in
constexpr float kFightNearM = 5.0f;   ///< closer than this it backs off
constexpr float kMaxPitchRad = 1.5f;  ///< within the protocol's ±π/2
/// Largest projectile speed (m/s) and gravity (m/s²) a WeaponSpec may give.
constexpr float kMaxShotSpeedMps = 1000;
constexpr float kMaxShotGravityMps2 = 1000;

float horizontal_distance(const Vec3& a, const Vec3& b) {
  return std::hypot(b[0] - a[0], b[2] - a[2]);
}

float yaw_towards(const Vec3& from, const Vec3& to) {
  // Forward for yaw ψ is (−sin ψ, 0, −cos ψ).
  return std::atan2(-(to[0] - from[0]), -(to[2] - from[2]));
}

using proto::ammo_of;

/// A WeaponSpec's flight, or what is wrong with it.
std::optional<ShotFlight> flight_of(const wire::WeaponSpec& spec, std::string& error) {
  const float speed = spec.projectile_speed_mps();
  if (!(speed >= 0 && speed <= kMaxShotSpeedMps)) {
    error = "projectile_speed_mps must be 0..1000, got " + std::to_string(speed);
    return std::nullopt;
  }
  if (spec.gravity_mps2_size() != 3) {
    error = "gravity_mps2 must hold 3 values, got " + std::to_string(spec.gravity_mps2_size());
    return std::nullopt;
  }
  double g2 = 0;
  for (const float g : spec.gravity_mps2()) g2 += double(g) * g;
  if (!std::isfinite(g2) || g2 > double(kMaxShotGravityMps2) * kMaxShotGravityMps2) {
    error = "gravity_mps2 must be finite, |g| <= 1000";
    return std::nullopt;
  }
  return ShotFlight{speed, -spec.gravity_mps2(1)};
}

}  // namespace

std::optional<Arsenal> arsenal_of(const wire::JoinMatchReply& reply, std::string& error) {
  Arsenal arsenal{};
  std::array<bool, proto::kWeaponCount> seen{};
  for (const wire::WeaponSpec& spec : reply.weapons()) {
    const std::optional<wire::Weapon> weapon = proto::weapon_of_slot(spec.weapon());
    if (!weapon) {
      error = "weapon " + std::to_string(spec.weapon()) + " is not 1.." +
              std::to_string(proto::kWeaponCount);
      return std::nullopt;
    }
    const std::string name = wire::Weapon_Name(*weapon);
    const std::size_t index = proto::slot_of(*weapon) - 1;
    if (seen[index]) {
      error = "weapon " + name + " given twice";
      return std::nullopt;
    }
    seen[index] = true;
    const std::optional<ShotFlight> flight = flight_of(spec, error);
    if (!flight) {
      error = "weapon " + name + ": " + error;
      return std::nullopt;
    }
    arsenal[index] = *flight;
  }
  for (std::size_t index = 0; index < seen.size(); ++index) {
    if (!seen[index]) {
      error = "no spec for weapon " + std::to_string(index + 1);
      return std::nullopt;
    }
  }
  return arsenal;
}

Brain::Brain(double skill, std::uint64_t seed)
    : skill_(std::clamp(skill, 0.0, 1.0)), random_(seed) {}

Brain::Aim Brain::aim_at(const SeenEntity& self, const SeenEntity& target,
                         wire::Weapon weapon) const {
  const Vec3 eye{self.position_m[0], self.position_m[1] + proto::kShotHeightM, self.position_m[2]};
  Vec3 point = target.position_m;
  const float distance = horizontal_distance(eye, point);
  const ShotFlight& shot = flight(weapon);
  if (weapon == wire::WEAPON_ROCKET_LAUNCHER && shot.speed_mps > 0) {
    // Lead a rocket by where the target will be when it arrives.
    const float t = distance / shot.speed_mps;
    for (int a = 0; a < 3; a += 2) point[a] += target.velocity_mps[a] * t;
  }
  Aim aim;
  aim.yaw = yaw_towards(eye, point);
  aim.pitch = std::atan2(point[1] - eye[1], std::max(distance, 0.01f));
  if (weapon == wire::WEAPON_GRENADE_LAUNCHER && shot.speed_mps > 0) {
    // A grenade flies a ballistic arc: the lower of the two angles that reach the distance.
    const float reach = distance * shot.drop_mps2 / (shot.speed_mps * shot.speed_mps);
    if (reach < 1) aim.pitch += 0.5f * std::asin(reach);
  }
  return aim;
}

wire::Weapon Brain::choose_weapon(const SeenEntity& self, const SeenEntity& target,
                                  const wire::PlayerStatus& status) const {
  const float distance = horizontal_distance(self.position_m, target.position_m);
  // Explosives only past their own blast (3.5 m), where they would not hurt the shooter.
  const bool explosives_ok = distance > kFightNearM && distance < 20;
  if (preferred_ != wire::WEAPON_RIFLE && explosives_ok && ammo_of(status, preferred_) > 0) {
    return preferred_;
  }
  if (ammo_of(status, wire::WEAPON_RIFLE) > 0) return wire::WEAPON_RIFLE;
  if (explosives_ok && ammo_of(status, wire::WEAPON_ROCKET_LAUNCHER) > 0) {
    return wire::WEAPON_ROCKET_LAUNCHER;
  }
  return wire::WEAPON_GRENADE_LAUNCHER;
}

std::optional<Vec3> Brain::wanted_pickup(const WorldView& view, const SeenEntity& self,
                                         const wire::PlayerStatus& status) const {
  const bool hurt = status.health() < 60;
  const bool unarmoured = status.armor() < 30;
  const bool short_of_ammo = ammo_of(status, weapon_) < 5;
  std::optional<Vec3> best;
  float best_d = 0;
  for (const auto& [index, pickup] : view.pickups()) {
    if (!pickup.up || !pickup.position_m) continue;
    const bool wanted = (pickup.kind == wire::PICKUP_KIND_HEALTH && hurt) ||
                        (pickup.kind == wire::PICKUP_KIND_ARMOR && unarmoured) ||
                        (pickup.kind == wire::PICKUP_KIND_AMMO && short_of_ammo);
    if (!wanted) continue;
    const float d = horizontal_distance(self.position_m, *pickup.position_m);
    if (!best || d < best_d) {
      best = pickup.position_m;
      best_d = d;
    }
  }
  return best;
}

Vec3 Brain::next_waypoint(const WorldView& view) {
  const auto& spawns = view.spawn_points();
  if (!spawns.empty() && std::uniform_int_distribution<int>(0, 3)(random_) != 0) {
    return spawns[std::uniform_int_distribution<std::size_t>(0, spawns.size() - 1)(random_)];
  }
  // Somewhere in the middle half of the map's box.
  Vec3 point{};
  for (int a = 0; a < 3; a += 2) {
    const float centre = 0.5f * (view.bounds().min_m[a] + view.bounds().max_m[a]);
    const float half = 0.25f * (view.bounds().max_m[a] - view.bounds().min_m[a]);
    point[a] = std::uniform_real_distribution<float>(centre - half, centre + half)(random_);
  }
  return point;
}

void Brain::steer(const Vec3& from, const Vec3& to, float yaw, wire::Input& input) const {
  const float dx = to[0] - from[0];
  const float dz = to[2] - from[2];
  const float length = std::hypot(dx, dz);
  if (length < 1e-3f) return;
  const float wx = dx / length;
  const float wz = dz / length;
  // In the yaw frame: forward (−sin ψ, −cos ψ), right (cos ψ, −sin ψ).
  const float forward = -wx * std::sin(yaw) - wz * std::cos(yaw);
  const float right = wx * std::cos(yaw) - wz * std::sin(yaw);
  input.set_move_forward(proto::move_steps(forward));
  input.set_move_right(proto::move_steps(right));
}

wire::Input Brain::decide(const WorldView& view, const wire::PlayerStatus& status, double now_s) {
  wire::Input input;
  input.set_yaw(last_yaw_);
  const SeenEntity* self = view.own();
  if (!self || !status.alive() || (self->flags & proto::kEntityDead)) return input;

  if (now_s >= error_until_s_) {
    const float sigma = static_cast<float>(1.0 - skill_) * kMaxAimErrorRad;
    if (sigma > 0) {
      std::normal_distribution<float> error(0.0f, sigma);
      yaw_error_ = error(random_);
      pitch_error_ = 0.5f * error(random_);
    } else {
      yaw_error_ = 0;
      pitch_error_ = 0;
    }
    error_until_s_ = now_s + kAimRedrawS;
  }
  if (now_s >= preference_until_s_) {
    // Mostly the rifle; now and then a spell with the rocket or the grenade launcher.
    const int draw = std::uniform_int_distribution<int>(0, 9)(random_);
    preferred_ = draw < 6   ? wire::WEAPON_RIFLE
                 : draw < 8 ? wire::WEAPON_ROCKET_LAUNCHER
                            : wire::WEAPON_GRENADE_LAUNCHER;
    preference_until_s_ = now_s + kPreferenceS;
  }
  if (now_s >= progress_check_s_) {
    const bool stuck = horizontal_distance(progress_from_, self->position_m) < kStuckM;
    jump_ = stuck;
    if (stuck) waypoint_.reset();
    progress_from_ = self->position_m;
    progress_check_s_ = now_s + kProgressCheckS;
  }

  float yaw = last_yaw_;
  const SeenEntity* enemy = view.nearest_enemy();
  const std::optional<Vec3> pickup = wanted_pickup(view, *self, status);
  if (enemy) {
    const wire::Weapon weapon = choose_weapon(*self, *enemy, status);
    const Aim aim = aim_at(*self, *enemy, weapon);
    yaw = aim.yaw + yaw_error_;
    input.set_pitch(std::clamp(aim.pitch + pitch_error_, -kMaxPitchRad, kMaxPitchRad));
    if (weapon != weapon_) {
      weapon_ = weapon;
      input.set_weapon_slot(proto::slot_of(weapon));
    }
    if (ammo_of(status, weapon_) > 0) input.set_buttons(proto::kButtonFire);
    if (now_s >= strafe_until_s_) {
      strafe_ = -strafe_;
      strafe_until_s_ = now_s + std::uniform_real_distribution<double>(0.8, 2.0)(random_);
    }
    if (pickup) {
      steer(self->position_m, *pickup, yaw, input);
    } else {
      const float distance = horizontal_distance(self->position_m, enemy->position_m);
      const float closing = distance > kFightFarM ? 1.0f : (distance < kFightNearM ? -1.0f : 0.0f);
      input.set_move_forward(static_cast<std::int32_t>(closing * proto::kMoveSteps));
      input.set_move_right(static_cast<std::int32_t>(strafe_ * 90));
    }
  } else {
    if (pickup) {
      waypoint_ = *pickup;
      waypoint_until_s_ = now_s + kWaypointS;
    }
    if (!waypoint_ || now_s >= waypoint_until_s_ ||
        horizontal_distance(self->position_m, *waypoint_) < kWaypointReachedM) {
      waypoint_ = next_waypoint(view);
      waypoint_until_s_ = now_s + kWaypointS;
    }
    yaw = yaw_towards(self->position_m, *waypoint_);
    steer(self->position_m, *waypoint_, yaw, input);
  }
  // Keep the yaw within (−π, π] so it always lies inside the protocol's ±2π.
  yaw = std::remainder(yaw, 2 * std::numbers::pi_v<float>);
  input.set_yaw(yaw);
  last_yaw_ = yaw;
  if (jump_) input.set_buttons(input.buttons() | proto::kButtonJump);
  return input;
}

}  // namespace ricochet::bot
