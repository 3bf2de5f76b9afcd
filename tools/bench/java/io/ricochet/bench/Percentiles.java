package io.ricochet.bench;

/**
 * Nearest-rank percentiles, the one definition every Ricochet figure uses
 * (stats/include/ricochet/stats/percentile.h): the p-th percentile of n samples is the sample of
 * rank ceil(p/100 * n) in ascending order (rank 1 when p is 0).
 */
final class Percentiles {
  private Percentiles() {}

  /** The 0-based index of the p-th percentile in {@code n} (> 0) sorted samples. */
  static int nearestRankIndex(int n, double percent) {
    double rank = Math.ceil(percent * n / 100.0); // percent * n first, as the C++ does
    rank = Math.max(1.0, Math.min(rank, n));
    return (int) rank - 1;
  }

  /** The p-th percentile of the first {@code n} samples of {@code sorted} (ascending). */
  static double ofSorted(double[] sorted, int n, double percent) {
    return n == 0 ? 0 : sorted[nearestRankIndex(n, percent)];
  }
}
