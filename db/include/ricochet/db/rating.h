#pragma once
/// Skill rating: Elo, generalised to matches of many players as pairwise duels.
///
/// Every pair of players that counts is one Elo game decided by score (higher wins, equal
/// draws):
///   expected_i = 1 / (1 + 10^((R_j - R_i) / 400)),  R_i += K / (N - 1) · Σ_j (actual - expected)
/// with K = 32 and N the number of players. In free-for-all every pair counts. In team
/// deathmatch only pairs across the two teams do, each decided by the team scores (a player's
/// score is its team's), so team-mates never rate each other. Dividing by N - 1 keeps a
/// free-for-all worth one duel's K however many play, and since each pair moves both sides by
/// the same amount the sum of all changes is zero (ratings are conserved) in either mode, even
/// with teams of different sizes. Elo over Glicko-2: one number per player, no rating periods to
/// schedule, and its behaviour is easy to explain to players.

#include <cstdint>
#include <vector>

namespace ricochet::db {

inline constexpr double kInitialRating = 1500;
inline constexpr double kEloK = 32;

struct RatedScore {
  double rating = kInitialRating;
  double score = 0;       ///< the player's score (free-for-all) or its team's (team deathmatch)
  std::int32_t team = 0;  ///< 0: free-for-all, every pair counts; otherwise only other teams
};

/// New ratings for the players of one match, in the same order.
std::vector<double> updated_ratings(const std::vector<RatedScore>& players);

}  // namespace ricochet::db
