package io.ricochet.client.core.predict;

import java.util.Arrays;

/**
 * Prediction errors (m) of one stats period, summarised as the nearest-rank percentiles of
 * stats/percentile.h: the p-th is the value at rank ceil(p/100 · n) of the sorted samples. Holds at
 * most {@link #CAPACITY} samples a period (later ones are dropped); sorting happens only in
 * {@link #summarise}. Not thread-safe.
 */
public final class ErrorWindow {
  /** Samples kept per period (a minute at 128 Hz). */
  public static final int CAPACITY = 8192;

  private final double[] samples = new double[CAPACITY];
  private final double[] sorted = new double[CAPACITY];
  private int count;

  /** Adds one error, m. */
  public void add(double errorM) {
    if (count < CAPACITY) samples[count++] = errorM;
  }

  /** Samples this period. */
  public int count() {
    return count;
  }

  /**
   * Writes p50, p99 and max (m) of this period into {@code out} (double[3], zeros without
   * samples) and starts a new period.
   */
  public void summarise(double[] out) {
    if (count == 0) {
      out[0] = out[1] = out[2] = 0;
      return;
    }
    System.arraycopy(samples, 0, sorted, 0, count);
    Arrays.sort(sorted, 0, count);
    out[0] = nearestRank(50, count);
    out[1] = nearestRank(99, count);
    out[2] = sorted[count - 1];
    count = 0;
  }

  private double nearestRank(double percentile, int n) {
    int rank = (int) Math.ceil(percentile / 100 * n);
    return sorted[Math.max(1, Math.min(n, rank)) - 1];
  }
}
