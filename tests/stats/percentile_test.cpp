#include "ricochet/stats/percentile.h"

#include <gtest/gtest.h>

#include <numeric>
#include <vector>

namespace ricochet::stats::percentile_test {
namespace {

/// 1, 2, ..., n: the sample of rank r is r.
std::vector<double> one_to(int n) {
  std::vector<double> samples(static_cast<std::size_t>(n));
  std::iota(samples.begin(), samples.end(), 1.0);
  return samples;
}

TEST(PercentileTest, EmptyIsZero) {
  EXPECT_EQ(percentile({}, 50), 0);
  EXPECT_EQ(percentile_of_sorted({}, 99), 0);
  EXPECT_EQ(median({}), 0);
}

TEST(PercentileTest, OneSampleIsEveryPercentile) {
  for (const double p : {0.0, 1.0, 50.0, 99.0, 100.0}) EXPECT_EQ(percentile({7.5}, p), 7.5) << p;
}

TEST(PercentileTest, P99OfAHundredIsTheNinetyNinthNotTheMaximum) {
  // rank ceil(0.99 * 100) = 99
  EXPECT_EQ(percentile(one_to(100), 99), 99);
  EXPECT_EQ(percentile(one_to(100), 100), 100);
  // rank ceil(0.99 * 1000) = 990; ceil(0.99 * 101) = ceil(99.99) = 100
  EXPECT_EQ(percentile(one_to(1000), 99), 990);
  EXPECT_EQ(percentile(one_to(101), 99), 100);
}

TEST(PercentileTest, P99BelowAHundredSamplesIsTheMaximum) {
  // ceil(0.99 * 99) = ceil(98.01) = 99; ceil(0.99 * 10) = ceil(9.9) = 10
  EXPECT_EQ(percentile(one_to(99), 99), 99);
  EXPECT_EQ(percentile(one_to(10), 99), 10);
}

TEST(PercentileTest, MedianOfAnEvenCountIsTheLowerMiddle) {
  EXPECT_EQ(median({4, 1, 3, 2}), 2);  // rank ceil(0.5 * 4) = 2
  EXPECT_EQ(median({5, 1, 3}), 3);     // rank ceil(1.5) = 2
  EXPECT_EQ(median({2, 1}), 1);
}

TEST(PercentileTest, EndsAreTheMinimumAndMaximum) {
  const std::vector<double> samples{9, -2, 4, 0.5};
  EXPECT_EQ(percentile(samples, 0), -2);
  EXPECT_EQ(percentile(samples, 100), 9);
}

TEST(PercentileTest, HandComputedRanks) {
  // 20 samples 10, 20, ..., 200: p95 rank 19, p50 rank 10, p25 rank 5, p1 rank ceil(0.2) = 1.
  std::vector<double> samples;
  for (int i = 20; i >= 1; --i) samples.push_back(10.0 * i);  // unsorted on purpose
  EXPECT_EQ(percentile(samples, 95), 190);
  EXPECT_EQ(percentile(samples, 50), 100);
  EXPECT_EQ(percentile(samples, 25), 50);
  EXPECT_EQ(percentile(samples, 1), 10);
  // 7 samples: p90 rank ceil(6.3) = 7, p80 rank ceil(5.6) = 6, p14 rank ceil(0.98) = 1
  EXPECT_EQ(nearest_rank_index(7, 90), 6u);
  EXPECT_EQ(nearest_rank_index(7, 80), 5u);
  EXPECT_EQ(nearest_rank_index(7, 14), 0u);
}

TEST(PercentileTest, SortedAndUnsortedAgree) {
  const std::vector<double> sorted = one_to(37);
  std::vector<double> shuffled(sorted.rbegin(), sorted.rend());
  for (const double p : {0.0, 5.0, 50.0, 95.0, 99.0, 100.0})
    EXPECT_EQ(percentile_of_sorted(sorted, p), percentile(shuffled, p)) << p;
}

TEST(PercentileTest, WholePercentsOfLargeCountsAreExact) {
  // A rank that is a whole number must not be pushed up by rounding: p95 of 20000 is rank 19000.
  EXPECT_EQ(nearest_rank_index(20000, 95), 18999u);
  EXPECT_EQ(nearest_rank_index(600, 99), 593u);  // the server's 600-tick window: rank 594
  EXPECT_EQ(nearest_rank_index(600, 50), 299u);
}

}  // namespace
}  // namespace ricochet::stats::percentile_test
