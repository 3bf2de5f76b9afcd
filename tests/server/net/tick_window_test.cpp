#include "tick_window.h"

#include <gtest/gtest.h>

namespace ricochet::server::tick_window_test {
namespace {

TEST(TickWindow, EmptyIsZeros) {
  const TickWindow window(10);
  EXPECT_EQ(window.size(), 0u);
  const stats::Summary s = window.summary();
  EXPECT_EQ(s.count, 0u);
  EXPECT_EQ(s.p50, 0);
  EXPECT_EQ(s.max, 0);
}

TEST(TickWindow, NearestRankQuantilesAndMax) {
  TickWindow window(100);
  for (int i = 100; i >= 1; --i) window.record(i * 0.001);  // 1 ms .. 100 ms, any order
  const stats::Summary s = window.summary();
  EXPECT_DOUBLE_EQ(s.p50, 0.050);
  EXPECT_DOUBLE_EQ(s.p95, 0.095);
  EXPECT_DOUBLE_EQ(s.p99, 0.099);  // rank 99 of 100: not the max
  EXPECT_DOUBLE_EQ(s.max, 0.100);
}

TEST(TickWindow, KeepsOnlyTheLastSamples) {
  TickWindow window(3);
  for (double s : {9.0, 9.0, 9.0, 1.0, 2.0, 3.0}) window.record(s);
  EXPECT_EQ(window.size(), 3u);
  EXPECT_DOUBLE_EQ(window.summary().max, 3.0);
  EXPECT_DOUBLE_EQ(window.summary().p50, 2.0);
}

}  // namespace
}  // namespace ricochet::server::tick_window_test
