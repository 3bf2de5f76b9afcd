// Elo over free-for-all matches (rating.h), against ratings computed by hand: the two-player
// case is textbook Elo, favourites gain less for a win than underdogs, and a free-for-all is
// pairwise duels at K / (N - 1).

#include "ricochet/db/rating.h"

#include <gtest/gtest.h>

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

TEST(Rating, ASoloMatchChangesNothing) {
  EXPECT_EQ(updated_ratings({{1500, 100}}), std::vector<double>{1500});
  EXPECT_TRUE(updated_ratings({}).empty());
}

}  // namespace
}  // namespace ricochet::db
