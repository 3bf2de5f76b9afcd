#include "ricochet/loadtest/flatness.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace ricochet::loadtest::flatness_test {
namespace {

constexpr FlatnessBounds kBounds{16.0, 10.0};

/// One point a second for `seconds`, RSS and fds on the lines given (per hour), with a
/// saw-tooth of `noise` on both (what a healthy server's allocator and churn look like).
std::vector<FlatnessPoint> series(int seconds, double rss_per_hour, double fds_per_hour,
                                  double noise = 0) {
  std::vector<FlatnessPoint> out;
  for (int s = 0; s < seconds; ++s) {
    const double hours = s / 3600.0;
    const double wiggle = noise * ((s % 7) - 3) / 3.0;
    out.push_back({static_cast<double>(s), 100 + rss_per_hour * hours + wiggle,
                   40 + fds_per_hour * hours + std::round(wiggle)});
  }
  return out;
}

TEST(LeastSquaresSlope, FitsALineExactly) {
  const std::vector<double> x{0, 1, 2, 3};
  const std::vector<double> y{5, 7, 9, 11};
  ASSERT_TRUE(least_squares_slope(x, y));
  EXPECT_DOUBLE_EQ(*least_squares_slope(x, y), 2.0);
  const std::vector<double> falling{3, 2, 1, 0};
  EXPECT_DOUBLE_EQ(*least_squares_slope(x, falling), -1.0);
}

TEST(LeastSquaresSlope, NoiseAroundAFlatLineHasASmallSlope) {
  const std::vector<double> x{0, 1, 2, 3, 4, 5};
  const std::vector<double> y{10, 12, 8, 12, 8, 10};
  EXPECT_NEAR(*least_squares_slope(x, y), 0.0, 0.3);
}

TEST(LeastSquaresSlope, RefusesWhatNoLineFits) {
  EXPECT_FALSE(least_squares_slope(std::vector<double>{1}, std::vector<double>{2}));
  EXPECT_FALSE(least_squares_slope(std::vector<double>{1, 2}, std::vector<double>{2}));
  EXPECT_FALSE(least_squares_slope(std::vector<double>{3, 3, 3}, std::vector<double>{1, 2, 3}));
}

TEST(Flatness, AHealthyHourIsFlatDespiteItsNoise) {
  const Flatness flat = judge_flatness(series(3600, 0, 0, 4), 360, kBounds);
  EXPECT_TRUE(flat.flat()) << flat.verdict();
  EXPECT_EQ(flat.verdict(), "flat");
  EXPECT_EQ(flat.samples, 3240);
  EXPECT_NEAR(*flat.rss_mib_per_hour, 0, 1);
  EXPECT_NEAR(*flat.fds_per_hour, 0, 1);
}

TEST(Flatness, ALeakBreaksItsBound) {
  // 27 MiB/h: 16 KiB per game connection at 1,700 connections an hour.
  const Flatness rss = judge_flatness(series(3600, 27, 0, 4), 360, kBounds);
  EXPECT_FALSE(rss.flat());
  EXPECT_FALSE(rss.rss_flat());
  EXPECT_TRUE(rss.fds_flat());
  EXPECT_NEAR(*rss.rss_mib_per_hour, 27, 1);
  EXPECT_EQ(rss.verdict().rfind("RSS grows 2", 0), 0u) << rss.verdict();  // 26.99 or 27.01
  EXPECT_NE(rss.verdict().find("MiB/h (bound 16.00)"), std::string::npos) << rss.verdict();
  // 60 fds/h: one descriptor per match.
  const Flatness fds = judge_flatness(series(3600, 0, 60, 4), 360, kBounds);
  EXPECT_TRUE(fds.rss_flat());
  EXPECT_FALSE(fds.fds_flat());
  EXPECT_EQ(fds.verdict().rfind("open fds grows ", 0), 0u) << fds.verdict();
  EXPECT_NE(fds.verdict().find("fds/h (bound 10.00)"), std::string::npos) << fds.verdict();
}

TEST(Flatness, TheWarmUpIsLeftOut) {
  // Fast growth for the first 10 minutes (start-up, the first matches), flat after.
  std::vector<FlatnessPoint> points = series(3600, 0, 0);
  for (FlatnessPoint& point : points) {
    if (point.t_s < 600) {
      point.rss_mib -= (600 - point.t_s) / 10;
      point.open_fds -= std::floor((600 - point.t_s) / 30);
    }
  }
  EXPECT_FALSE(judge_flatness(points, 0, kBounds).flat());
  EXPECT_TRUE(judge_flatness(points, 600, kBounds).flat());
}

TEST(Flatness, TooFewSamplesAreNotFlat) {
  const Flatness flat = judge_flatness(series(100, 0, 0), 98, kBounds);
  EXPECT_EQ(flat.samples, 2);
  EXPECT_FALSE(flat.flat());
  EXPECT_FALSE(flat.rss_mib_per_hour);
  EXPECT_NE(flat.verdict().find("too few samples"), std::string::npos);
}

}  // namespace
}  // namespace ricochet::loadtest::flatness_test
