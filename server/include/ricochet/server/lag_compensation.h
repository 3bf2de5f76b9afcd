#pragma once
/// Lag-compensated hitscan: every player's sphere per tick for the last second in a ring, and a
/// ray tested against the map and the other players where the shooter's client showed them,
/// without moving a live body.
///
/// Follows Source's player lag compensation (source-sdk-2013 mp/src/game/server/
/// player_lagcompensation.cpp, CLagCompensationManager::StartLagCompensation and
/// BacktrackPlayer; developer.valvesoftware.com/wiki/Source_Multiplayer_Networking, "Lag
/// compensation"): command execution time = now - one-way latency - the client's view
/// interpolation delay, capped (sv_maxunlag); the tick the client says it showed is used only
/// while it is within 200 ms of that estimate; a target is placed by interpolating the two
/// stored ticks around the view time and never extrapolated (a view at or after the newest tick
/// takes the newest); a target with no valid track back to the view time (it respawned or was
/// teleported since, Source's "lost track", or it was not alive then) is tested where it is now;
/// the shooter is never rewound. Unlike Source, a claim outside the window is clamped into it
/// (and counted) instead of replaced by the estimate, and nothing is moved and restored: the
/// rewound players are sphere proxies of one query (physics::World::ray_cast_spheres).

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "ricochet/physics/query.h"
#include "ricochet/physics/types.h"
#include "ricochet/physics/world.h"

namespace ricochet::server {

struct LagCompensationConfig {
  float history_s = 1.0f;                ///< s kept per player, 0.1..2
  float max_rewind_ms = 250;             ///< ms, the total rewind cap, 0..history_s
  float claim_tolerance_ms = 200;        ///< ms, |claimed view - expected view| trusted, 0..1000
  float interpolation_delay_ms = 33.3f;  ///< ms, the client's interpolation delay the server
                                         ///< assumes (two 60 Hz snapshots), 0..250
  bool enabled = true;                   ///< false: shots test the current positions

  /// Empty when valid; otherwise names the field, the allowed range and what came.
  std::string validate() const;
};

/// One player after one step.
struct LagSample {
  std::uint32_t entity_id = 0;
  physics::BodyId body;
  physics::Vec3 position_m = physics::Vec3::Zero();  ///< m, the sphere's centre
  float radius_m = 0;                                ///< m
  std::uint32_t life = 0;  ///< bumps at every respawn or teleport: no rewind across a change
  bool hittable = false;   ///< alive (dead players are not shot)
};

/// What the shooter saw, from LagCompensation::resolve.
struct ViewTime {
  std::uint32_t tick = 0;  ///< the older of the two stored ticks the view lies between
  float fraction = 0;      ///< 0..1, past `tick` towards tick + 1
  double rewind_ms = 0;    ///< ms, now - view, after clamping
  bool clamped = false;    ///< the claim was outside the window and was clamped into it
};

class LagCompensation {
 public:
  /// `config` must be valid (validate() empty); `tick_rate_hz` is the match's fixed rate
  /// (TickClockConfig, 10..128).
  LagCompensation(const LagCompensationConfig& config, int tick_rate_hz);

  /// Stores the players after step `tick` (call after every step, ticks increasing). The ring
  /// reuses its storage: nothing is allocated once it has seen as many players as it will hold.
  void record(std::uint32_t tick, std::span<const LagSample> players);

  /// The view a shot at `now_tick` (the newest recorded step, the state the shot is tested
  /// against) is tested at: now - one-way latency - interpolation delay, or the client's claim
  /// (`claimed_tick` + proto::view_fraction_ticks(`claimed_fraction`)) clamped to within
  /// claim_tolerance_ms of that estimate, to 0..max_rewind_ms, and never ahead of now.
  /// `claimed_tick` 0: no claim, the estimate is used. `one_way_latency_ms`: ms, the transport's
  /// RTT / 2 (not finite or negative counts as 0). Disabled: now.
  ViewTime resolve(std::uint32_t now_tick, std::uint32_t claimed_tick,
                   std::uint8_t claimed_fraction, double one_way_latency_ms) const;

  /// Replaces `out` with the spheres of every hittable player of the newest tick but the shooter,
  /// where they were at `view` (interpolated between the two stored ticks around it, the oldest
  /// stored tick for a view older than the ring). A player whose life differs at either of the
  /// two ticks from its life now, who was not hittable then, or who has no sample then, is where
  /// it is now. SphereProxy::user_data is the entity id, body its body.
  void rewound_targets(const ViewTime& view, std::uint32_t shooter_entity,
                       std::vector<physics::SphereProxy>& out) const;

  /// The lag-compensated hitscan: a ray from `origin` (m) along `direction` (need not be unit)
  /// for `max_distance` m against the world's static shapes (no live body) and
  /// rewound_targets(view, shooter_entity). The shooter is neither rewound nor hit. On a hit,
  /// `hit.target.user_data` is the entity id and `hit.target.body` the player's body, or
  /// `hit.target.shape` is the static shape in the way.
  bool cast(const physics::World& world, const physics::Vec3& origin,
            const physics::Vec3& direction, physics::Real max_distance, const ViewTime& view,
            std::uint32_t shooter_entity, physics::RayHit& hit) const;

  /// Claims resolve() clamped since construction.
  std::uint64_t clamped_claims() const { return clamped_claims_; }

 private:
  struct Slot {
    std::uint32_t tick = 0;
    bool used = false;
    std::vector<LagSample> samples;
  };

  const Slot* slot_of(std::uint32_t tick) const;
  double tick_ms() const { return 1000.0 / tick_rate_hz_; }

  LagCompensationConfig config_;
  int tick_rate_hz_;
  std::vector<Slot> ring_;
  std::uint32_t newest_tick_ = 0;
  std::uint32_t oldest_tick_ = 0;
  bool any_ = false;
  mutable std::uint64_t clamped_claims_ = 0;
  mutable std::vector<physics::SphereProxy> scratch_;  ///< cast()'s targets, reused
};

}  // namespace ricochet::server
