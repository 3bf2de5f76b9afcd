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
  private final double[] recent = new double[CAPACITY]; // a ring of the newest samples
  private long added;

  /** Adds one error, m. */
  public void add(double errorM) {
    if (count < CAPACITY) samples[count++] = errorM;
    recent[(int) (added++ % CAPACITY)] = errorM;
  }

  /**
   * The nearest-rank p99 (m) of the newest {@link #CAPACITY} samples over every period (about two
   * minutes at 60 Hz): the figure of a whole play, where one period's 60 samples make its p99 its
   * maximum. 0 without samples.
   */
  public double recentP99() {
    int n = (int) Math.min(added, CAPACITY);
    if (n == 0) return 0;
    System.arraycopy(recent, 0, sorted, 0, n);
    Arrays.sort(sorted, 0, n);
    return nearestRank(99, n);
  }

  /** Samples over every period so far. */
  public long total() {
    return added;
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
