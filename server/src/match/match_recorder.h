#pragma once
/// A match's recording (recording.h): the membership changes between steps, each step's inputs
/// and, every hash_interval_ticks steps, the match hash (match_recording.cpp).

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "match_combat.h"
#include "match_rules.h"
#include "ricochet/physics/world.h"
#include "ricochet/server/match.h"
#include "ricochet/server/recording.h"
#include "roster.h"

namespace ricochet::server {

struct Recorder {
  std::vector<RecordedInput> step_inputs;     ///< this step's
  std::vector<RecordedEvent> pending_events;  ///< since the last step
  std::unique_ptr<RecordingWriter> writer;    ///< null: not recording (or taken)

  /// Keeps a membership change for the next step's record.
  void note(const RecordedEvent& event) {
    if (writer) pending_events.push_back(event);
  }
  /// The step `tick` is recorded with the match hash.
  bool hash_due(std::uint32_t tick, int hash_interval_ticks) const {
    return writer && !writer->full() && tick % static_cast<std::uint32_t>(hash_interval_ticks) == 0;
  }
};

/// Writes step `tick`: the pending events, the step's inputs and `hash` when given; stops the
/// recording (recording_truncated) when it is full.
void record_step(std::uint32_t tick, std::optional<std::uint64_t> hash, Recorder& recorder,
                 MatchCounters& counters);

/// What recordings check (Match::state_hash): the world's state_hash() and every game rule's
/// state (health, armour, ammunition, scores, timers, pickups, projectiles, the generator).
std::uint64_t match_hash(const physics::World& world, std::uint32_t tick, const RulesState& rules,
                         const Roster& roster, const Combat& combat);

}  // namespace ricochet::server
