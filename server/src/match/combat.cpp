/// Health and armour, the match RNG, aim and spread, explosions and input checks (combat.h).

#include "ricochet/server/combat.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "ricochet/physics/scene_profile.h"

namespace ricochet::server {

namespace {

using physics::Real;
using physics::Vec3;

constexpr Real kPi = std::numbers::pi_v<Real>;
/// How far off the surface a rocket explodes at least, m (explosion_center).
constexpr Real kMinSurfaceOffsetM = Real(0.05);

/// round(value) with halves up, for values >= 0.
int round_half_up(double value) {
  return static_cast<int>(std::floor(value + 0.5));
}

std::uint64_t rotl(std::uint64_t x, int k) {
  return (x << k) | (x >> (64 - k));
}

std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/// Two unit vectors perpendicular to unit `axis` and to each other.
void orthonormal_basis(const Vec3& axis, Vec3& u, Vec3& v) {
  const Vec3 helper = std::abs(axis.x()) < Real(0.9) ? Vec3::UnitX() : Vec3::UnitY();
  u = axis.cross(helper).normalized();
  v = axis.cross(u);
}

}  // namespace

DamageResult apply_damage(Vitals& target, int damage, float armor_absorb) {
  DamageResult result;
  if (damage <= 0 || target.health <= 0) return result;
  const double absorb = armor_absorb > 0 ? std::min(double(armor_absorb), 1.0) : 0.0;
  const int armor_share =
      std::min(round_half_up(double(damage) * absorb), std::max(target.armor, 0));
  const int health_share = damage - armor_share;
  result.armor_lost = armor_share;
  result.health_lost = std::min(health_share, target.health);
  target.armor -= result.armor_lost;
  target.health -= result.health_lost;
  result.killed = target.health == 0;
  return result;
}

float damage_scale(const WeaponsConfig& config, bool self, bool teammate) {
  if (self) return config.self_damage_scale;
  if (teammate) return config.friendly_fire ? config.friendly_fire_scale : 0.0f;
  return 1.0f;
}

int scaled_damage(int damage, float scale) {
  if (damage <= 0 || !(scale > 0)) return 0;
  return round_half_up(double(damage) * std::min(double(scale), 1.0));
}

MatchRng::MatchRng(std::uint64_t seed) {
  for (std::uint64_t& word : s_) word = splitmix64(seed);
}

std::uint64_t MatchRng::next() {
  const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
  const std::uint64_t t = s_[1] << 17;
  s_[2] ^= s_[0];
  s_[3] ^= s_[1];
  s_[1] ^= s_[2];
  s_[0] ^= s_[3];
  s_[2] ^= t;
  s_[3] = rotl(s_[3], 45);
  return result;
}

float MatchRng::uniform() {
  return static_cast<float>(next() >> 40) * 0x1.0p-24f;
}

Vec3 aim_direction(float yaw_rad, float pitch_rad) {
  const Real cos_pitch = std::cos(Real(pitch_rad));
  return Vec3(-std::sin(Real(yaw_rad)) * cos_pitch, std::sin(Real(pitch_rad)),
              -std::cos(Real(yaw_rad)) * cos_pitch);
}

Vec3 spread_direction(const Vec3& aim, float spread_rad, MatchRng& rng) {
  const Vec3 axis = aim.normalized();
  if (!(spread_rad > 0)) return axis;
  // Uniform over the cap's solid angle: cos θ uniform in [cos spread, 1], φ uniform.
  const Real cos_theta = 1 - Real(rng.uniform()) * (1 - std::cos(Real(spread_rad)));
  const Real sin_theta = std::sqrt(std::max(Real(0), 1 - cos_theta * cos_theta));
  const Real phi = 2 * kPi * Real(rng.uniform());
  Vec3 u, v;
  orthonormal_basis(axis, u, v);
  return (axis * cos_theta + (u * std::cos(phi) + v * std::sin(phi)) * sin_theta).normalized();
}

Vec3 eye_position(const Vec3& player_center_m) {
  return player_center_m + Vec3(0, Real(proto::kShotHeightM), 0);
}

Vec3 explosion_center(const physics::ProjectileHitEvent& hit, const WeaponConfig& weapon) {
  return hit.point + hit.normal * std::max(Real(weapon.projectile_radius_m), kMinSurfaceOffsetM);
}

void explosion_effects(const physics::World& world, const Vec3& center_m,
                       const WeaponConfig& weapon, std::span<const ExplosionTarget> targets,
                       std::vector<ExplosionEffect>& out) {
  const Real radius = Real(weapon.explosion_radius_m);
  if (!(radius > 0)) return;
  physics::QueryFilter statics_only;
  statics_only.bodies = false;
  for (std::size_t i = 0; i < targets.size(); ++i) {
    const ExplosionTarget& target = targets[i];
    const Vec3 offset = target.center_m - center_m;
    const Real center_distance = offset.norm();
    if (!std::isfinite(center_distance)) continue;
    const Real surface_distance = std::max(Real(0), center_distance - Real(target.radius_m));
    if (surface_distance >= radius) continue;
    if (surface_distance > 0) {
      physics::RayHit hit;
      if (world.ray_cast_closest(center_m, offset, surface_distance, statics_only, hit)) continue;
    }
    const Real falloff = 1 - surface_distance / radius;
    Vec3 direction = Vec3::UnitY();
    if (center_distance > Real(1e-4)) {
      direction = (offset / center_distance + Vec3(0, Real(kKnockbackUpwardBias), 0)).normalized();
    }
    out.push_back(
        ExplosionEffect{.target = i,
                        .damage = round_half_up(double(weapon.damage) * double(falloff)),
                        .impulse_ns = direction * (Real(weapon.explosion_impulse_ns) * falloff)});
  }
}

Vec3 capped_explosion_velocity(const Vec3& before, const Vec3& pushed, Real cap_mps) {
  const Real limit = std::max(cap_mps, before.norm());
  const Real speed = pushed.norm();
  if (!(speed > limit)) return pushed;
  return pushed * (limit / speed);
}

const char* name(Violation violation) {
  switch (violation) {
    case Violation::TurnRate:
      return "turn_rate";
    case Violation::FireRate:
      return "fire_rate";
    case Violation::InputRate:
      return "input_rate";
    case Violation::ViewTick:
      return "view_tick";
  }
  return "unknown";
}

bool turn_rate_ok(float prev_yaw, float prev_pitch, float yaw, float pitch, float max_rad) {
  if (!std::isfinite(prev_yaw) || !std::isfinite(prev_pitch) || !std::isfinite(yaw) ||
      !std::isfinite(pitch)) {
    return false;
  }
  // remainder() maps the difference into [-π, π]: the short way round.
  const double yaw_change = std::remainder(double(yaw) - double(prev_yaw), 2 * std::numbers::pi);
  const double pitch_change = double(pitch) - double(prev_pitch);
  return std::abs(yaw_change) <= max_rad && std::abs(pitch_change) <= max_rad;
}

}  // namespace ricochet::server
