#pragma once
/// Combat math: health and armour, the match's random numbers, aim and spread, explosions, and
/// the checks of what a player's inputs claim. Pure functions of their arguments (the RNG of its
/// seed), so a match replays exactly.

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "ricochet/physics/events.h"
#include "ricochet/physics/types.h"
#include "ricochet/physics/world.h"
#include "ricochet/server/weapons.h"

namespace ricochet::server {

// --- health and armour ---

inline constexpr int kMaxHealth = 100;
inline constexpr int kMaxArmor = 100;

struct Vitals {
  int health = kMaxHealth;  ///< 0 is dead
  int armor = 0;
};

struct DamageResult {
  int health_lost = 0;  ///< what the target lost, never more than it had (overkill is not counted)
  int armor_lost = 0;
  bool killed = false;  ///< this hit took the health to 0
};

/// Armour takes round(damage × armor_absorb) (halves up) while it lasts, health the rest; health
/// stops at 0. Damage <= 0, or a target already dead, changes nothing. armor_absorb is taken
/// within 0..1 (NaN as 0). Integer arithmetic but for that one rounding, so deterministic.
DamageResult apply_damage(Vitals& target, int damage, float armor_absorb);

/// The factor of a hit's damage: own explosions self_damage_scale; a teammate's (same non-None
/// team, not oneself) 0, or friendly_fire_scale when friendly_fire; anyone else 1.
float damage_scale(const WeaponsConfig& config, bool self, bool teammate);
/// round(damage × scale), halves up, scale taken within 0..1 (NaN as 0).
int scaled_damage(int damage, float scale);

// --- random numbers ---

/// The match's deterministic generator: xoshiro256** seeded through splitmix64 (so any seed,
/// 0 included, gives a good state). Same seed, same sequence, on every platform.
class MatchRng {
 public:
  explicit MatchRng(std::uint64_t seed);
  std::uint64_t next();
  /// Uniform in [0, 1), 24 random bits.
  float uniform();

 private:
  std::uint64_t s_[4];
};

// --- aim ---

/// Unit view direction: yaw about +Y counter-clockwise seen from above, 0 along -Z; pitch
/// positive looks up. (0, 0) → (0, 0, -1); yaw π/2 → (-1, 0, 0); pitch π/2 → (0, 1, 0).
physics::Vec3 aim_direction(float yaw_rad, float pitch_rad);
/// A direction uniform over the cone of half-angle spread_rad around `aim` (normalised here);
/// `aim` itself, drawing nothing, when spread_rad <= 0; otherwise it draws two numbers.
physics::Vec3 spread_direction(const physics::Vec3& aim, float spread_rad, MatchRng& rng);
/// Where a player at `player_center_m` shoots from: proto::kShotHeightM above its centre.
physics::Vec3 eye_position(const physics::Vec3& player_center_m);

// --- explosions ---

/// Where a rocket explodes: its centre at impact, off the surface it hit (hit point + normal ×
/// max(radius, 5 cm)), so the line-of-sight rays start outside the wall.
physics::Vec3 explosion_center(const physics::ProjectileHitEvent& hit, const WeaponConfig& weapon);

/// Something an explosion may reach: a player or a prop sphere.
struct ExplosionTarget {
  physics::BodyId body;
  physics::Vec3 center_m;
  float radius_m = 0;
};

struct ExplosionEffect {
  std::size_t target = 0;                            ///< index into the targets given
  int damage = 0;                                    ///< before damage_scale
  physics::Vec3 impulse_ns = physics::Vec3::Zero();  ///< N·s, for World::apply_impulse
};

/// Unit vertical part added to the centre→target direction of the knockback before it is
/// normalised again: a blast beside a player also lifts it (rocket jumps off walls).
inline constexpr float kKnockbackUpwardBias = 0.25f;

/// Appends (out is not cleared) one effect per target within reach, in target order. Damage and
/// impulse fall off linearly from the weapon's values at distance 0 (from `center_m` to the
/// target's surface; 0 when inside it) to 0 at explosion_radius_m; damage rounds halves up. The
/// impulse points along centre→target plus kKnockbackUpwardBias up (straight up when the centres
/// coincide). A target whose centre the explosion cannot see (a ray from `center_m` towards the
/// target's centre hits a static shape before the target's surface) takes nothing.
void explosion_effects(const physics::World& world, const physics::Vec3& center_m,
                       const WeaponConfig& weapon, std::span<const ExplosionTarget> targets,
                       std::vector<ExplosionEffect>& out);

/// The velocity a body keeps after an explosion pushed it from `before` to `pushed` (m/s):
/// `pushed`, scaled down along its direction to the larger of `cap_mps` and the speed before
/// when it is faster than both. An explosion then never makes a body faster than the cap (the
/// match gives its snapshots' max_speed_mps, so clients see what the server simulates: a 0.4 kg
/// grenade would otherwise leave a 500 N·s blast at over 1000 m/s) and never slows a body that
/// was already faster.
physics::Vec3 capped_explosion_velocity(const physics::Vec3& before, const physics::Vec3& pushed,
                                        physics::Real cap_mps);

// --- input checks ---

/// What a player's inputs claim beyond what a person can do; the match counts and logs them.
enum class Violation : std::uint8_t {
  TurnRate,   ///< yaw or pitch changed by more than max_turn_rate_rad_s × dt in one tick
  FireRate,   ///< fire pressed (a new edge) faster than the weapon's fire interval over a window
  InputRate,  ///< more inputs in a 1 s window than input_rate_limit()
  ViewTick,   ///< a view tick claim outside the lag compensation window (clamped)
};
inline constexpr std::size_t kViolationCount = static_cast<std::size_t>(Violation::ViewTick) + 1;
/// "turn_rate", "fire_rate", "input_rate", "view_tick".
const char* name(Violation violation);

/// Whether a view moved from (prev_yaw, prev_pitch) to (yaw, pitch) within max_rad on each axis,
/// yaw taken the short way round (3.1 → -3.1 is 0.08 rad, and -2π..2π are all one circle).
/// False for a non-finite angle.
bool turn_rate_ok(float prev_yaw, float prev_pitch, float yaw, float pitch, float max_rad);

/// Inputs a player may send in a 1 s window: 1.25 × the tick rate + 8 (clients run a little
/// fast, and resend after a stall).
inline constexpr int input_rate_limit(int tick_rate_hz) {
  return tick_rate_hz * 5 / 4 + 8;
}

}  // namespace ricochet::server
