#pragma once
/// Percentiles by the nearest-rank definition, the one every figure of Ricochet uses (the
/// server's /metrics, the bot, the load test, the benches).
///
/// Nearest rank: the p-th percentile of n samples is the sample of rank ceil(p/100 * n) in
/// ascending order (ranks 1..n; rank 1 when p is 0). It is always one of the samples, never an
/// interpolation between two, and at least p % of the samples are ≤ it. What that gives for a
/// small n:
///   - p50 of an even n is the lower of the two middle samples (median of 1, 2, 3, 4 is 2);
///   - p99 is the maximum whenever n < 100; of exactly 100 samples it is the 99th, the second
///     largest; from 100 on, p99 leaves out the top floor(n/100) samples at most;
///   - p100 is the maximum, p0 the minimum.
/// A figure computed before this library with another definition (a "p99" of 100 samples that
/// was the maximum) stays as it was recorded in tools/bench/results/; lines since are nearest
/// rank.

#include <cstddef>
#include <span>
#include <vector>

namespace ricochet::stats {

/// The 0-based index of the nearest-rank p-th percentile in n samples sorted ascending.
/// n: > 0. percent: 0..100.
std::size_t nearest_rank_index(std::size_t n, double percent);

/// The p-th percentile (percent: 0..100) of samples sorted ascending; 0 when empty.
double percentile_of_sorted(std::span<const double> sorted, double percent);

/// The p-th percentile (percent: 0..100) of samples in any order; 0 when empty.
double percentile(std::vector<double> samples, double percent);

/// The median: the 50th percentile by the same definition; 0 when empty.
double median(std::vector<double> samples);

}  // namespace ricochet::stats
