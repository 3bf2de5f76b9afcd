#include "ricochet/stats/summary.h"

#include <algorithm>

#include "ricochet/stats/percentile.h"

namespace ricochet::stats {

double mean(std::span<const double> samples) {
  if (samples.empty()) return 0;
  double sum = 0;
  for (const double sample : samples) sum += sample;
  return sum / static_cast<double>(samples.size());
}

Summary summarize(std::vector<double> samples) {
  if (samples.empty()) return {};
  Summary summary;
  summary.count = samples.size();
  summary.mean = mean(samples);  // summed in the order taken, as a running total would be
  std::sort(samples.begin(), samples.end());
  summary.min = samples.front();
  summary.p50 = percentile_of_sorted(samples, 50);
  summary.p95 = percentile_of_sorted(samples, 95);
  summary.p99 = percentile_of_sorted(samples, 99);
  summary.max = samples.back();
  return summary;
}

}  // namespace ricochet::stats
