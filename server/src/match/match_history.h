#pragma once
/// A match's entity states by tick (match.h: entity_states, states_at; the snapshots are built
/// from it), and the read-out of the world's bodies after each step into the players, the
/// projectiles and the lag compensation ring.

#include <cstdint>
#include <span>
#include <vector>

#include "match_combat.h"
#include "ricochet/physics/world.h"
#include "ricochet/proto/snapshot_codec.h"
#include "roster.h"

namespace ricochet::server {

struct HistoryEntry {
  std::uint32_t tick = 0;
  std::vector<proto::EntityState> states;  ///< sorted by id
};

struct History {
  /// Keeps the last `ticks` steps (1..1024).
  explicit History(int ticks) : ring(static_cast<std::size_t>(ticks)) {}

  std::vector<HistoryEntry> ring;  ///< by tick % size (config.history_ticks)
  // Scratch for World::read_bodies.
  std::vector<physics::BodyId> body_ids;
  std::vector<physics::Vec3> positions, velocities;

  /// The states after step `tick` while it is in the ring; empty otherwise.
  std::span<const proto::EntityState> states_at(std::uint32_t tick) const;
};

/// After the step `tick`: reads the live bodies into the players' and projectiles' positions
/// and velocities, records the players in the lag compensation ring (combat.lag) and their
/// entity states, with the projectiles', in the history.
void record_history(std::uint32_t tick, const physics::World& world, Roster& roster, Combat& combat,
                    History& history);

}  // namespace ricochet::server
