#include "ricochet/stats/summary.h"

#include <gtest/gtest.h>

#include <vector>

namespace ricochet::stats::summary_test {
namespace {

TEST(SummaryTest, EmptyIsAllZeros) {
  const Summary s = summarize({});
  EXPECT_EQ(s.count, 0u);
  EXPECT_EQ(s.mean, 0);
  EXPECT_EQ(s.max, 0);
  EXPECT_EQ(mean(std::vector<double>{}), 0);
}

TEST(SummaryTest, HandComputedFigures) {
  // 1..200 in reverse: mean 100.5, p50 rank 100, p95 rank 190, p99 rank 198.
  std::vector<double> samples;
  for (int i = 200; i >= 1; --i) samples.push_back(i);
  const Summary s = summarize(samples);
  EXPECT_EQ(s.count, 200u);
  EXPECT_DOUBLE_EQ(s.mean, 100.5);
  EXPECT_EQ(s.min, 1);
  EXPECT_EQ(s.p50, 100);
  EXPECT_EQ(s.p95, 190);
  EXPECT_EQ(s.p99, 198);
  EXPECT_EQ(s.max, 200);
}

TEST(SummaryTest, OneOutlierInAHundredShowsInTheMaxNotTheP99) {
  std::vector<double> samples(99, 1.0);
  samples.push_back(50.0);
  const Summary s = summarize(samples);
  EXPECT_EQ(s.p99, 1.0);
  EXPECT_EQ(s.max, 50.0);
  EXPECT_DOUBLE_EQ(s.mean, 1.49);
}

}  // namespace
}  // namespace ricochet::stats::summary_test
