#include "ricochet/stats/percentile.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <utility>

namespace ricochet::stats {

std::size_t nearest_rank_index(std::size_t n, double percent) {
  assert(n > 0 && percent >= 0 && percent <= 100);
  // percent * n first: exact for whole percents, so 99 % of 100 is rank 99, not 99.0000001 -> 100.
  const double rank = std::ceil(percent * static_cast<double>(n) / 100.0);
  const double clamped = std::clamp(rank, 1.0, static_cast<double>(n));
  return static_cast<std::size_t>(clamped) - 1;
}

double percentile_of_sorted(std::span<const double> sorted, double percent) {
  if (sorted.empty()) return 0;
  return sorted[nearest_rank_index(sorted.size(), percent)];
}

double percentile(std::vector<double> samples, double percent) {
  if (samples.empty()) return 0;
  const auto nth =
      samples.begin() + static_cast<std::ptrdiff_t>(nearest_rank_index(samples.size(), percent));
  std::nth_element(samples.begin(), nth, samples.end());
  return *nth;
}

double median(std::vector<double> samples) {
  return percentile(std::move(samples), 50);
}

}  // namespace ricochet::stats
