#pragma once
/// The last few hundred tick times of one match, for exact quantiles over a recent window (the
/// per-phase histograms' buckets double in width: too coarse to tell 3 ms from 4 ms). Not
/// thread-safe: the owner locks.

#include <array>
#include <cstddef>
#include <vector>

namespace ricochet::server {

class TickWindow {
 public:
  /// capacity: > 0 samples (600: 10 s at 60 Hz).
  explicit TickWindow(std::size_t capacity) : samples_(capacity, 0.0) {}

  /// One tick's duration, s.
  void record(double seconds);
  std::size_t size() const { return filled_; }
  /// p50, p95, p99 (nearest rank) and the max of the samples held, s; zeros when empty.
  std::array<double, 4> quantiles() const;

 private:
  std::vector<double> samples_;
  std::size_t next_ = 0;
  std::size_t filled_ = 0;
};

}  // namespace ricochet::server
