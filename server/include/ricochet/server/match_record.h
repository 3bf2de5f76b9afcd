#pragma once
/// Who counts in a match's record, and for how long, from the match's own scoreboard: on
/// simulation ticks, not the wall clock, so the record needs no socket to test and a replay of
/// the recording gives the same one.
///
/// A player counts when it took part while the match was running: connected for at least one
/// running tick, or it killed or died then (an entity away within its reconnect grace can still
/// die, and its rocket can still kill). Players who only waited or warmed up do not: nothing of
/// theirs counted. Its time played is its running ticks connected over the tick rate.

#include <span>
#include <vector>

#include "ricochet/server/rules.h"

namespace ricochet::server {

/// One player of a match's record.
struct CountedPlayer {
  PlayerScore score;
  double seconds_played = 0;  ///< s: running ticks connected / tick rate
};

/// Took part while the match was running (above).
bool counts_in_record(const PlayerScore& score);

/// The players of `scoreboard` (Match::scoreboard()) who count, in its order, their time played
/// at `tick_rate_hz` (the match's, 10..128).
std::vector<CountedPlayer> counted_players(std::span<const PlayerScore> scoreboard,
                                           int tick_rate_hz);

}  // namespace ricochet::server
