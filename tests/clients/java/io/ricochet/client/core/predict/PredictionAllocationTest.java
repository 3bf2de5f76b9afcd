package io.ricochet.client.core.predict;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import io.ricochet.client.core.snapshot.QuantizationSpec;
import java.lang.management.ManagementFactory;
import org.junit.jupiter.api.Test;

/**
 * Warm prediction allocates nothing per tick: inputs applied, snapshots reconciled with replays,
 * others interpolated, in a world of a plane, a box and a mesh, with 0 bytes allocated on the
 * thread (com.sun.management.ThreadMXBean, JDK-only, hence only in a test).
 */
class PredictionAllocationTest {
  private static final int RATE = 60;
  private static final int TICKS = 2000;

  private final com.sun.management.ThreadMXBean threads =
      (com.sun.management.ThreadMXBean) ManagementFactory.getThreadMXBean();
  private static byte[] sink;

  private final CollisionWorld world = Worlds.of(Worlds.empty()
                                                     .addPlanes(Worlds.plane(0, 1, 0, -5))
                                                     .addBoxes(Worlds.box(3, 1, 0, 1, 1, 1))
                                                     .addMeshes(Worlds.floorMesh(0, 10)));
  private final Predictor predictor = new Predictor(world, QuantizationSpec.defaults(), RATE);
  private final Interpolator interpolator = new Interpolator(RATE);
  private final long[] ids = {1, 2, 3};
  private final float[] positions = new float[9];
  private final float[] own = {0, 0.4f, 0};
  private final float[] ownVelocity = new float[3];
  private final float[] shown = new float[3];
  private final double[] summary = new double[3];
  private long sequence;
  private long tick;

  @Test
  void aWarmPredictionAllocatesNothingPerTick() {
    assertTrue(threads.isThreadAllocatedMemorySupported());
    threads.setThreadAllocatedMemoryEnabled(true);
    assertTrue(measure(() -> sink = new byte[4096]) >= 4096, "the measure sees an allocation");
    for (int warm = 0; warm < 5; ++warm) play();
    long allocated = Long.MAX_VALUE;
    for (int measured = 0; measured < 3; ++measured)
      allocated = Math.min(allocated, measure(this::play));
    assertEquals(0, allocated, "bytes allocated over " + TICKS + " warm ticks");
    assertTrue(predictor.replayed() > TICKS, "replayed " + predictor.replayed());
  }

  /** TICKS ticks: an input each, a snapshot every tick acknowledging the input 3 ticks back. */
  private void play() {
    for (int i = 0; i < TICKS; ++i) {
      ++sequence;
      ++tick;
      predictor.apply(sequence, (int) (sequence % 255) - 127, 100, 0.01f * (sequence % 600),
          sequence % 90 == 0 ? 1 : 0);
      predictor.predicted(own, ownVelocity);
      if (Math.abs(own[0]) > 8 || Math.abs(own[2]) > 8 || own[1] < -1) {
        own[0] = 0;
        own[1] = 0.4f;
        own[2] = 0;
      }
      predictor.reconcile(tick, true, own, ownVelocity, Math.max(0, sequence - 3));
      for (int k = 0; k < 9; ++k) positions[k] = (k + 1) * 0.1f * (tick % 50);
      interpolator.add(tick, 3, ids, positions, tick * 16_667);
      interpolator.position(2, interpolator.renderTick(tick * 16_667 + 5000), shown);
      interpolator.viewTick(tick * 16_667);
      interpolator.viewFraction(tick * 16_667);
      if (predictor.errors().count() == ErrorWindow.CAPACITY) predictor.errors().summarise(summary);
    }
  }

  private long measure(Runnable work) {
    long id = Thread.currentThread().getId();
    long before = threads.getThreadAllocatedBytes(id);
    work.run();
    return threads.getThreadAllocatedBytes(id) - before;
  }
}
