#pragma once
/// Skill rating: Elo, generalised to free-for-all matches as pairwise duels.
///
/// Every pair of players in a match is one Elo game decided by score (higher wins, equal draws):
///   expected_i = 1 / (1 + 10^((R_j - R_i) / 400)),  R_i += K / (N - 1) · Σ_j (actual - expected)
/// with K = 32. Dividing by N - 1 keeps a match worth one duel's K however many play, and the sum
/// of all changes is zero (ratings are conserved). Elo over Glicko-2: one number per player, no
/// rating periods to schedule, and its behaviour is easy to explain to players.

#include <vector>

namespace ricochet::db {

inline constexpr double kInitialRating = 1500;
inline constexpr double kEloK = 32;

struct RatedScore {
  double rating = kInitialRating;
  double score = 0;
};

/// New ratings for the players of one match, in the same order.
std::vector<double> updated_ratings(const std::vector<RatedScore>& players);

}  // namespace ricochet::db
