#pragma once
/// The state of a match's rules (rules.h): the phase and its ticks, the scores of the teams, why
/// it ended, the generator and the map's pickups. The phases that change it are in match_game.h.

#include <array>
#include <cstdint>
#include <vector>

#include "ricochet/server/combat.h"
#include "ricochet/server/map.h"
#include "ricochet/server/rules.h"
#include "ricochet/wire/game.pb.h"

namespace ricochet::server {

struct PickupState {
  MapPickup spot;
  bool available = true;
  std::uint32_t respawn_tick = 0;
};

struct RulesState {
  explicit RulesState(std::uint64_t seed) : rng(seed) {}

  MatchPhase phase = MatchPhase::Waiting;
  std::uint32_t phase_started_tick = 0;
  std::uint32_t phase_ends_tick = 0;  ///< 0: open-ended
  std::array<int, 3> team_scores{};   ///< by wire::Team
  wire::MatchEndReason end_reason = wire::MATCH_END_REASON_UNSPECIFIED;
  MatchRng rng;                      ///< rifle spread; hashed
  std::vector<PickupState> pickups;  ///< the map's, in order

  /// Scores count only while the match is running.
  bool counts() const { return phase == MatchPhase::Running; }
  bool ended() const { return phase == MatchPhase::Ended; }
};

}  // namespace ricochet::server
