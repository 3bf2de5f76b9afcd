#pragma once
/// The phases of a match's step that take the inputs and move the players (match_movement.cpp).

#include <cstdint>
#include <vector>

#include "ricochet/physics/world.h"
#include "ricochet/server/match.h"
#include "ricochet/server/movement.h"
#include "ricochet/server/recording.h"
#include "roster.h"

namespace ricochet::server {

/// Each connected player's input for this step, from its buffer (the last one repeated when
/// none came), into player.applied and `step_inputs` (for the recording). Players away keep the
/// neutral input disconnect() left.
void apply_inputs(Roster& roster, std::vector<RecordedInput>& step_inputs, MatchCounters& counters);

/// Sets each living player's velocity from its applied input; notes whether it stands on
/// something. `step_s`: s.
void move_players(const MovementConfig& movement, double step_s, Roster& roster,
                  physics::World& world);

/// Steps the world by `step_s` (s) and counts the tick.
void step_physics(double step_s, physics::World& world, std::uint32_t& tick);

}  // namespace ricochet::server
