/// Elo over pairwise duels, free-for-all or across teams (rating.h).

#include "ricochet/db/rating.h"

#include <cmath>

namespace ricochet::db {

std::vector<double> updated_ratings(const std::vector<RatedScore>& players) {
  const std::size_t n = players.size();
  std::vector<double> next(n);
  for (std::size_t i = 0; i < n; ++i) next[i] = players[i].rating;
  if (n < 2) return next;
  const double k = kEloK / static_cast<double>(n - 1);
  for (std::size_t i = 0; i < n; ++i) {
    double change = 0;
    for (std::size_t j = 0; j < n; ++j) {
      if (i == j) continue;
      if (players[i].team != 0 && players[i].team == players[j].team) continue;  // team-mates
      const double expected =
          1 / (1 + std::pow(10.0, (players[j].rating - players[i].rating) / 400));
      const double actual = players[i].score > players[j].score    ? 1.0
                            : players[i].score == players[j].score ? 0.5
                                                                   : 0.0;
      change += actual - expected;
    }
    next[i] += k * change;
  }
  return next;
}

}  // namespace ricochet::db
