#pragma once
/// The last few hundred tick times of one match, for exact quantiles over a recent window (the
/// per-phase histograms' buckets double in width: too coarse to tell 3 ms from 4 ms). Not
/// thread-safe: the owner locks.

#include <cstddef>
#include <vector>

#include "ricochet/stats/summary.h"

namespace ricochet::server {

class TickWindow {
 public:
  /// capacity: > 0 samples (600: 10 s at 60 Hz).
  explicit TickWindow(std::size_t capacity) : samples_(capacity, 0.0) {}

  /// One tick's duration, s.
  void record(double seconds);
  std::size_t size() const { return filled_; }
  /// The samples held, s: percentiles by nearest rank (ricochet/stats/percentile.h), max, mean;
  /// all zeros when empty.
  stats::Summary summary() const;

 private:
  std::vector<double> samples_;
  std::size_t next_ = 0;
  std::size_t filled_ = 0;
};

}  // namespace ricochet::server
