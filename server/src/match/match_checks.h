#pragma once
/// What a player's inputs claim, checked against what the rules allow, and where a violation is
/// counted and logged (match_checks.cpp).

#include <cstdint>

#include "ricochet/server/match.h"
#include "roster.h"

namespace ricochet::server {

/// Where a violation goes besides the player's own count: the match's counters and its log.
struct ViolationReport {
  std::uint32_t match_id = 0;
  const MatchLog& log;
  MatchCounters& counters;
};

/// Counts `violation` for `player` and the match; logs the first, then every power of two.
void note_violation(Player& player, Violation violation, const ViolationReport& report);

/// The turn rate: each player's aim follows its applied input, at most max_turn_rate_rad_s
/// over `step_s` (s). Reads the applied inputs, writes the accepted aims.
void check_inputs(const WeaponsConfig& weapons, double step_s, Roster& roster,
                  const ViolationReport& report);

}  // namespace ricochet::server
