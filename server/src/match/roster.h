#pragma once
/// A match's seats (match.h): the players, each a connection part and a game part, sorted by
/// entity id; the scores of those who left; the entity ids the players and projectiles share.

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "ricochet/physics/world.h"
#include "ricochet/proto/clock.h"
#include "ricochet/proto/snapshot_codec.h"
#include "ricochet/server/combat.h"
#include "ricochet/server/input_buffer.h"
#include "ricochet/server/rules.h"
#include "ricochet/server/weapons.h"

namespace ricochet::server {

/// One seat of a match, keyed by account: who sits there, its connection (what the network side
/// changes: connect, disconnect, receive, the snapshots) and its game (what the step changes).
struct Player {
  std::uint64_t account = 0;
  std::string name;
  std::uint32_t entity_id = 0;

  // --- the connection ---
  bool connected = true;
  proto::TimeUs disconnected_at = 0;
  InputBuffer inputs;
  PlayerInput applied;                                ///< this step's input
  std::unique_ptr<proto::SnapshotEncoder> snapshots;  ///< per connection, none while away
  /// The newest snapshot tick the client acknowledged since the last snapshot (0: none),
  /// handed to `snapshots` when the next one is built: the encoder stays cold between ticks.
  std::uint32_t snapshot_ack = 0;
  proto::TimeUs latency_us = 0;          ///< one way
  std::uint32_t input_window_start = 0;  ///< tick the input-rate window began
  std::uint32_t inputs_in_window = 0;    ///< new inputs offered in it

  // --- the game ---
  physics::BodyId body;  ///< null while dead
  bool grounded = false;
  Team team = Team::None;
  Vitals vitals;
  bool alive = true;
  std::uint32_t life = 0;                            ///< bumps at every spawn (lag compensation)
  std::uint32_t respawn_tick = 0;                    ///< while dead
  std::uint32_t protected_until = 0;                 ///< no damage before this tick
  physics::Vec3 position_m = physics::Vec3::Zero();  ///< after the last step (or at death)
  physics::Vec3 velocity_mps = physics::Vec3::Zero();
  WeaponKind weapon = WeaponKind::Rifle;
  std::array<int, kWeaponCount> ammo{};
  std::uint32_t next_fire_tick = 0;  ///< the weapon is ready at this tick
  std::uint32_t previous_buttons = 0;
  float aim_yaw_rad = 0, aim_pitch_rad = 0;  ///< the aim the checks accepted
  bool aimed = false;                        ///< aim_* hold a previous aim
  PlayerScore score;
  std::array<std::uint64_t, kViolationCount> violations{};
};

/// The players of a match and who has left it.
struct Roster {
  std::vector<Player> players;        ///< sorted by entity id (ids only grow)
  std::vector<PlayerScore> departed;  ///< scores of players who left and count (match_record.h)
  std::uint32_t next_entity_id = 1;   ///< shared by players and projectiles

  std::uint32_t new_entity_id() { return next_entity_id++; }
  Player* find(std::uint64_t account);
  const Player* find(std::uint64_t account) const;
  Player* find_entity(std::uint32_t entity_id);
  int connected_count() const;
  /// Every seated player and every departed score, by entity.
  std::vector<PlayerScore> scoreboard() const;
};

}  // namespace ricochet::server
