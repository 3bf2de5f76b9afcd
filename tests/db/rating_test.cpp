// Elo over free-for-all matches (rating.h), against ratings computed by hand: the two-player
// case is textbook Elo, favourites gain less for a win than underdogs, and a free-for-all is
// pairwise duels at K / (N - 1).

#include "ricochet/db/rating.h"

#include <gtest/gtest.h>

namespace ricochet::db::rating_test {
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

TEST(Rating, FreeForAllIsPairwiseDuelsWithKOverNMinusOne) {
  // By hand: K / (N - 1) = 32 / 3 per duel. The 1500 player beat all three, expected
  // 1 / (1 + 10^(100/400)) = 0.359935 against 1600, 0.640065 against 1400 and
  // 1 / (1 + 10^(50/400)) = 0.428537 against 1550: 1500 + 32/3 * (3 - 1.428537) = 1516.762273.
  const std::vector<double> next = updated_ratings({{1500, 30}, {1600, 20}, {1400, 10}, {1550, 0}});
  ASSERT_EQ(next.size(), 4u);
  EXPECT_NEAR(next[0], 1516.762273, 1e-6);
  EXPECT_NEAR(next[1], 1600.306400, 1e-6);
  EXPECT_NEAR(next[2], 1401.100767, 1e-6);
  EXPECT_NEAR(next[3], 1531.830560, 1e-6);
}

TEST(Rating, TeamMatesNeverRateEachOther) {
  // 2 v 2, red (team 1) won 30 to 10: each red player beat both blue ones, K / (N - 1) = 32 / 3
  // per duel, expected 0.5 between equals: +32/3 * (2 - 1) each; the red pair's own difference
  // in rating changes nothing between them.
  const std::vector<double> next =
      updated_ratings({{1500, 30, 1}, {1500, 30, 1}, {1500, 10, 2}, {1500, 10, 2}});
  EXPECT_NEAR(next[0], 1500 + 32.0 / 3, 1e-9);
  EXPECT_NEAR(next[1], 1500 + 32.0 / 3, 1e-9);
  EXPECT_NEAR(next[2], 1500 - 32.0 / 3, 1e-9);
  EXPECT_NEAR(next[3], 1500 - 32.0 / 3, 1e-9);
  // Team-mates alone: no pair counts.
  EXPECT_EQ(updated_ratings({{1600, 5, 2}, {1400, 5, 2}}), (std::vector<double>{1600, 1400}));
}

TEST(Rating, UnevenTeamsAreConserved) {
  // 1 v 3, the lone blue player lost: it duelled three opponents, each of them one.
  const std::vector<double> next =
      updated_ratings({{1500, 2, 2}, {1450, 9, 1}, {1550, 9, 1}, {1500, 9, 1}});
  double sum = 0;
  for (const double r : next) sum += r;
  EXPECT_NEAR(sum, 1500 + 1450 + 1550 + 1500, 1e-9);
  EXPECT_LT(next[0], 1500);
  // By hand for the red 1450: one duel against 1500, expected 1 / (1 + 10^(50/400)) = 0.428537.
  EXPECT_NEAR(next[1], 1450 + 32.0 / 3 * (1 - 0.428537), 1e-5);
}

TEST(Rating, ASoloMatchChangesNothing) {
  EXPECT_EQ(updated_ratings({{1500, 100}}), std::vector<double>{1500});
  EXPECT_TRUE(updated_ratings({}).empty());
}

}  // namespace
}  // namespace ricochet::db::rating_test
