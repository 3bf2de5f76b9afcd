#include "tick_window.h"

#include <gtest/gtest.h>

namespace ricochet::server {
namespace {

TEST(TickWindow, EmptyIsZeros) {
  const TickWindow window(10);
  EXPECT_EQ(window.size(), 0u);
  EXPECT_EQ(window.quantiles(), (std::array<double, 4>{0, 0, 0, 0}));
}

TEST(TickWindow, NearestRankQuantilesAndMax) {
  TickWindow window(100);
  for (int i = 100; i >= 1; --i) window.record(i * 0.001);  // 1 ms .. 100 ms, any order
  const auto q = window.quantiles();
  EXPECT_DOUBLE_EQ(q[0], 0.050);
  EXPECT_DOUBLE_EQ(q[1], 0.095);
  EXPECT_DOUBLE_EQ(q[2], 0.099);
  EXPECT_DOUBLE_EQ(q[3], 0.100);
}

TEST(TickWindow, KeepsOnlyTheLastSamples) {
  TickWindow window(3);
  for (double s : {9.0, 9.0, 9.0, 1.0, 2.0, 3.0}) window.record(s);
  EXPECT_EQ(window.size(), 3u);
  EXPECT_DOUBLE_EQ(window.quantiles()[3], 3.0);
  EXPECT_DOUBLE_EQ(window.quantiles()[0], 2.0);
}

}  // namespace
}  // namespace ricochet::server
