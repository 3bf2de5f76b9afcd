#pragma once
/// A bot's behaviour, one decision per tick from what it sees (WorldView) and its own status:
/// wander between places players spawn at, chase the nearest enemy, aim at it with an error
/// that shrinks with skill, hold fire while aimed, pick the weapon for the distance and the
/// ammunition, and walk to a known pickup when hurt. Sans-IO: time is a parameter, randomness
/// comes from a seeded generator, so a decision sequence is reproducible. It leads rockets and
/// lobs grenades with the match's numbers, from the join reply's weapons (Arsenal).

#include <array>
#include <cstdint>
#include <optional>
#include <random>
#include <string>

#include "ricochet/bot/world_view.h"
#include "ricochet/proto/weapon_wire.h"
#include "ricochet/wire/control.pb.h"
#include "ricochet/wire/game.pb.h"

namespace ricochet::bot {

/// Aim error at skill 0, rad (standard deviation per axis); skill s scales it by (1 - s).
inline constexpr float kMaxAimErrorRad = 0.25f;

/// How a weapon's shot flies (WeaponSpec of the join reply).
struct ShotFlight {
  float speed_mps = 0;  ///< at launch, m/s; 0: hitscan
  float drop_mps2 = 0;  ///< downward acceleration in flight (minus gravity's y), m/s²
};
/// The match's weapons, by wire::Weapon - 1.
using Arsenal = std::array<ShotFlight, proto::kWeaponCount>;

/// The weapons of a join reply: nothing, with `error` set, when a weapon is missing or given
/// twice, or its speed (0..1000 m/s) or gravity (3 finite values, |g| <= 1000 m/s²) is wrong.
std::optional<Arsenal> arsenal_of(const wire::JoinMatchReply& reply, std::string& error);

class Brain {
 public:
  /// skill: 0..1. Until set_weapons(), every weapon counts as hitscan.
  Brain(double skill, std::uint64_t seed);

  /// The weapons of the match joined.
  void set_weapons(const Arsenal& arsenal) { arsenal_ = arsenal; }

  /// The input for this tick; sequence, view_tick and weapon bookkeeping are the caller's.
  /// now_s: the bot's clock, s.
  wire::Input decide(const WorldView& view, const wire::PlayerStatus& status, double now_s);

 private:
  struct Aim {
    float yaw = 0;
    float pitch = 0;
  };
  Aim aim_at(const SeenEntity& self, const SeenEntity& target, wire::Weapon weapon) const;
  const ShotFlight& flight(wire::Weapon weapon) const {
    return arsenal_[static_cast<std::size_t>(weapon) - 1];
  }
  wire::Weapon choose_weapon(const SeenEntity& self, const SeenEntity& target,
                             const wire::PlayerStatus& status) const;
  std::optional<Vec3> wanted_pickup(const WorldView& view, const SeenEntity& self,
                                    const wire::PlayerStatus& status) const;
  Vec3 next_waypoint(const WorldView& view);
  void steer(const Vec3& from, const Vec3& to, float yaw, wire::Input& input) const;

  double skill_;
  std::mt19937_64 random_;
  Arsenal arsenal_{};
  wire::Weapon weapon_ = wire::WEAPON_RIFLE;
  wire::Weapon preferred_ = wire::WEAPON_RIFLE;  ///< redrawn every kPreferenceS
  double preference_until_s_ = 0;
  // Aim error, redrawn every kAimRedrawS.
  float yaw_error_ = 0;
  float pitch_error_ = 0;
  double error_until_s_ = -1;
  // Wandering.
  std::optional<Vec3> waypoint_;
  double waypoint_until_s_ = 0;
  Vec3 progress_from_{};
  double progress_check_s_ = 0;
  bool jump_ = false;
  // Strafing while fighting.
  float strafe_ = 1;
  double strafe_until_s_ = 0;
  float last_yaw_ = 0;
};

}  // namespace ricochet::bot
