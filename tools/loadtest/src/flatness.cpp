#include "ricochet/loadtest/flatness.h"

#include <cstdio>

namespace ricochet::loadtest {

namespace {

constexpr double kSecondsPerHour = 3600;
/// A line through two points says nothing about noise; three is the least that does.
constexpr int kMinSamples = 3;

std::string slope_text(const char* what, const std::optional<double>& slope, double bound,
                       const char* unit) {
  char text[160];
  if (!slope) {
    std::snprintf(text, sizeof text, "%s: too few samples after the warm-up", what);
  } else {
    std::snprintf(text, sizeof text, "%s grows %.2f %s (bound %.2f)", what, *slope, unit, bound);
  }
  return text;
}

}  // namespace

std::optional<double> least_squares_slope(std::span<const double> xs, std::span<const double> ys) {
  if (xs.size() != ys.size() || xs.size() < 2) return std::nullopt;
  const auto n = static_cast<double>(xs.size());
  double mean_x = 0;
  double mean_y = 0;
  for (std::size_t i = 0; i < xs.size(); ++i) {
    mean_x += xs[i];
    mean_y += ys[i];
  }
  mean_x /= n;
  mean_y /= n;
  double covariance = 0;
  double variance = 0;
  for (std::size_t i = 0; i < xs.size(); ++i) {
    covariance += (xs[i] - mean_x) * (ys[i] - mean_y);
    variance += (xs[i] - mean_x) * (xs[i] - mean_x);
  }
  if (variance <= 0) return std::nullopt;
  return covariance / variance;
}

std::string Flatness::verdict() const {
  if (flat()) return "flat";
  std::string out;
  if (!rss_flat()) out = slope_text("RSS", rss_mib_per_hour, bounds.rss_mib_per_hour, "MiB/h");
  if (!fds_flat()) {
    if (!out.empty()) out += "; ";
    out += slope_text("open fds", fds_per_hour, bounds.fds_per_hour, "fds/h");
  }
  return out;
}

Flatness judge_flatness(const std::vector<FlatnessPoint>& points, double warmup_s,
                        const FlatnessBounds& bounds) {
  Flatness out;
  out.warmup_s = warmup_s;
  out.bounds = bounds;
  std::vector<double> t;
  std::vector<double> rss;
  std::vector<double> fds;
  for (const FlatnessPoint& point : points) {
    if (point.t_s < warmup_s) continue;
    t.push_back(point.t_s / kSecondsPerHour);
    rss.push_back(point.rss_mib);
    fds.push_back(point.open_fds);
  }
  out.samples = static_cast<int>(t.size());
  if (out.samples < kMinSamples) return out;
  out.rss_mib_per_hour = least_squares_slope(t, rss);
  out.fds_per_hour = least_squares_slope(t, fds);
  return out;
}

}  // namespace ricochet::loadtest
