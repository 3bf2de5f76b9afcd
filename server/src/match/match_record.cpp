/// Who counts in a match's record, and for how long (match_record.h).

#include "ricochet/server/match_record.h"

namespace ricochet::server {

bool counts_in_record(const PlayerScore& score) {
  return score.ticks_played > 0 || score.kills > 0 || score.deaths > 0;
}

std::vector<CountedPlayer> counted_players(std::span<const PlayerScore> scoreboard,
                                           int tick_rate_hz) {
  std::vector<CountedPlayer> counted;
  for (const PlayerScore& score : scoreboard) {
    if (!counts_in_record(score)) continue;
    counted.push_back({score, static_cast<double>(score.ticks_played) / tick_rate_hz});
  }
  return counted;
}

}  // namespace ricochet::server
