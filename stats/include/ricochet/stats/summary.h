#pragma once
/// The figures a bench or a report gives of a set of samples: count, mean, minimum, the usual
/// percentiles (nearest rank, percentile.h) and maximum, in the samples' unit.

#include <cstddef>
#include <span>
#include <vector>

namespace ricochet::stats {

/// The arithmetic mean; 0 when empty.
double mean(std::span<const double> samples);

struct Summary {
  std::size_t count = 0;
  double mean = 0;
  double min = 0;
  double p50 = 0;
  double p95 = 0;
  double p99 = 0;
  double max = 0;
};

/// Every field of Summary over the samples; all zeros when empty.
Summary summarize(std::vector<double> samples);

}  // namespace ricochet::stats
