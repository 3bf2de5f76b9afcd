#pragma once
/// Whether a soak's server stayed flat: the least-squares slope of its resident memory and of its
/// open file descriptors over the samples after a warm-up, each against a bound. Pure functions.

#include <optional>
#include <span>
#include <string>
#include <vector>

namespace ricochet::loadtest {

/// The least-squares slope of ys against xs (y units per x unit); nullopt with fewer than two
/// points, sizes that differ, or every x equal.
std::optional<double> least_squares_slope(std::span<const double> xs, std::span<const double> ys);

/// One look at the server during a soak.
struct FlatnessPoint {
  double t_s = 0;      ///< since the run started
  double rss_mib = 0;  ///< resident set size, MiB
  double open_fds = 0;
};

struct FlatnessBounds {
  double rss_mib_per_hour = 0;  ///< the largest RSS slope that is flat, MiB/hour
  double fds_per_hour = 0;      ///< the largest open-fd slope that is flat, fds/hour
};

struct Flatness {
  double warmup_s = 0;  ///< samples before this are left out
  int samples = 0;      ///< after the warm-up
  /// Slopes after the warm-up, per hour; nullopt: too few samples to fit a line.
  std::optional<double> rss_mib_per_hour;
  std::optional<double> fds_per_hour;
  FlatnessBounds bounds;

  bool rss_flat() const { return rss_mib_per_hour && *rss_mib_per_hour <= bounds.rss_mib_per_hour; }
  bool fds_flat() const { return fds_per_hour && *fds_per_hour <= bounds.fds_per_hour; }
  /// Both slopes fitted and within their bounds (a falling slope is flat).
  bool flat() const { return rss_flat() && fds_flat(); }
  /// "flat" or what is not ("RSS grows 40.1 MiB/h (bound 16); too few samples ...").
  std::string verdict() const;
};

/// Fits both slopes over the points at or after `warmup_s` (at least three are needed).
Flatness judge_flatness(const std::vector<FlatnessPoint>& points, double warmup_s,
                        const FlatnessBounds& bounds);

}  // namespace ricochet::loadtest
