package io.ricochet.client.core.predict;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;

import org.junit.jupiter.api.Test;

/** Others shown 100 ms behind, between two snapshots, held (never extrapolated) past the newest. */
class InterpolatorTest {
  private static final int RATE = 60;
  private static final long TICK_US = 1_000_000L / RATE;

  /** Entity 7 moves 1 m along x per tick; snapshot tick t arrives at t ticks of local time. */
  private static Interpolator withTicks(long first, long last) {
    Interpolator interpolator = new Interpolator(RATE);
    for (long tick = first; tick <= last; ++tick) {
      interpolator.add(tick, 1, new long[] {7}, new float[] {tick, 0, 0}, tick* TICK_US);
    }
    return interpolator;
  }

  @Test
  void othersAreShownOneHundredMillisecondsBehindTheNewestSnapshot() {
    Interpolator interpolator = withTicks(1, 100);
    long now = 100 * TICK_US; // the newest (tick 100) just arrived
    assertEquals(94.0, interpolator.renderTick(now), 1e-9); // 100 ms = 6 ticks at 60 Hz
    float[] p = new float[3];
    assertTrue(interpolator.position(7, interpolator.renderTick(now), p));
    assertEquals(94f, p[0], 1e-5f);
    assertEquals(94, interpolator.viewTick(now));
    assertEquals(0, interpolator.viewFraction(now));
  }

  @Test
  void betweenTwoSnapshotsThePositionIsInterpolatedAndTheViewFractionSaysWhere() {
    Interpolator interpolator = new Interpolator(RATE);
    interpolator.add(10, 1, new long[] {7}, new float[] {0, 0, 0}, 10 * TICK_US);
    interpolator.add(20, 1, new long[] {7}, new float[] {10, 0, 0}, 20 * TICK_US);
    long now = 20 * TICK_US + TICK_US / 4; // render tick 14.25
    float[] p = new float[3];
    double render = interpolator.renderTick(now);
    assertEquals(14.25, render, 1e-3);
    assertTrue(interpolator.position(7, render, p));
    assertEquals(4.25f, p[0], 1e-3f);
    assertEquals(14, interpolator.viewTick(now));
    assertEquals(64, interpolator.viewFraction(now), 1); // a quarter of 256
  }

  @Test
  void whenSnapshotsStopTheLastOneIsHeldNotExtrapolated() {
    Interpolator interpolator = withTicks(1, 50);
    long later = 80 * TICK_US; // 30 ticks without a snapshot
    assertEquals(50.0, interpolator.renderTick(later), 1e-9);
    float[] p = new float[3];
    assertTrue(interpolator.position(7, interpolator.renderTick(later), p));
    assertEquals(50f, p[0], 0f); // where tick 50 said, not 74
    assertTrue(interpolator.position(7, 1000, p));
    assertEquals(50f, p[0], 0f);
    assertEquals(50, interpolator.viewTick(later));
  }

  @Test
  void anEntityMissingFromOneOfTheTwoSnapshotsIsHeldWhereTheOtherHasIt() {
    Interpolator interpolator = new Interpolator(RATE);
    interpolator.add(10, 1, new long[] {7}, new float[] {1, 2, 3}, 0);
    interpolator.add(11, 1, new long[] {8}, new float[] {5, 5, 5}, TICK_US);
    float[] p = new float[3];
    assertTrue(interpolator.position(7, 10.5, p));
    assertEquals(1f, p[0], 0f);
    assertTrue(interpolator.position(8, 10.5, p));
    assertEquals(5f, p[0], 0f);
    assertFalse(interpolator.position(9, 10.5, p));
  }

  @Test
  void aLateOrRepeatedSnapshotIsIgnored() {
    Interpolator interpolator = withTicks(1, 10);
    interpolator.add(5, 1, new long[] {7}, new float[] {-100, 0, 0}, 11 * TICK_US);
    float[] p = new float[3];
    assertTrue(interpolator.position(7, 5, p));
    assertEquals(5f, p[0], 0f);
  }
}
