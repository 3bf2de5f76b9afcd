// Elo over free-for-all matches (rating.h): the two-player case is textbook Elo, changes sum to
// zero, and favourites gain less for a win than underdogs.

#include "ricochet/db/rating.h"

#include <gtest/gtest.h>

#include <numeric>

namespace ricochet::db {
namespace {

TEST(Rating, EqualPlayersMoveByHalfK) {
  const std::vector<double> next = updated_ratings({{1500, 10}, {1500, 3}});
  EXPECT_DOUBLE_EQ(next[0], 1516);
  EXPECT_DOUBLE_EQ(next[1], 1484);
}

TEST(Rating, ADrawBetweenEqualsChangesNothing) {
  const std::vector<double> next = updated_ratings({{1500, 5}, {1500, 5}});
  EXPECT_DOUBLE_EQ(next[0], 1500);
  EXPECT_DOUBLE_EQ(next[1], 1500);
}

TEST(Rating, TextbookExpectationFor400PointGap) {
  // Expected score of the 1900 player against 1500: 1 / (1 + 10^-1) = 0.909...
  const std::vector<double> next = updated_ratings({{1900, 1}, {1500, 0}});
  EXPECT_NEAR(next[0] - 1900, 32 * (1 - 1 / 1.1), 1e-9);
  EXPECT_NEAR(next[1] - 1500, -32 * (1 - 1 / 1.1), 1e-9);
  // The underdog winning gains much more.
  const std::vector<double> upset = updated_ratings({{1900, 0}, {1500, 1}});
  EXPECT_NEAR(upset[1] - 1500, 32 * (1 / 1.1), 1e-9);
}

TEST(Rating, FreeForAllConservesRatingAndOrdersByScore) {
  const std::vector<RatedScore> players = {{1500, 30}, {1600, 20}, {1400, 10}, {1550, 0}};
  const std::vector<double> next = updated_ratings(players);
  double before = 0, after = 0;
  for (std::size_t i = 0; i < players.size(); ++i) before += players[i].rating, after += next[i];
  EXPECT_NEAR(after, before, 1e-9);
  EXPECT_GT(next[0], 1500);  // top score gains
  EXPECT_LT(next[3], 1550);  // last loses
  // One match is worth at most K for a player however many play.
  for (std::size_t i = 0; i < players.size(); ++i)
    EXPECT_LE(std::abs(next[i] - players[i].rating), kEloK);
}

TEST(Rating, ASoloMatchChangesNothing) {
  EXPECT_EQ(updated_ratings({{1500, 100}}), std::vector<double>{1500});
  EXPECT_TRUE(updated_ratings({}).empty());
}

}  // namespace
}  // namespace ricochet::db
