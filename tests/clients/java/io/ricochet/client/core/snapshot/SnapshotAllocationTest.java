package io.ricochet.client.core.snapshot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import io.ricochet.wire.SnapshotProto.Snapshot;
import java.lang.management.ManagementFactory;
import java.util.ArrayList;
import java.util.List;
import org.junit.jupiter.params.ParameterizedTest;
import org.junit.jupiter.params.provider.ValueSource;

/**
 * A warm decoder allocates nothing per snapshot (a phone's garbage collector is a frame drop): the
 * vector streams, replayed round after round with their ticks moved on by a multiple of the ring,
 * decode with 0 bytes allocated on the decoding thread, measured as the bench does with
 * com.sun.management.ThreadMXBean (JDK-only, hence only here).
 */
class SnapshotAllocationTest {
  private static final long ROUND_TICKS = 1L << 20; // a multiple of the ring's 64 slots
  private static final int WARM_ROUNDS = 5;
  private static final int MEASURED_ROUNDS = 3;

  private final com.sun.management.ThreadMXBean threads =
      (com.sun.management.ThreadMXBean) ManagementFactory.getThreadMXBean();

  @ParameterizedTest
  @ValueSource(strings = {"snapshots_spheres901", "snapshots_players64"})
  void aWarmDecoderAllocatesNothingPerSnapshot(String set) throws Exception {
    assertTrue(threads.isThreadAllocatedMemorySupported());
    threads.setThreadAllocatedMemoryEnabled(true);
    assertTrue(measure(() -> sink = new byte[4096]) >= 4096, "the measure sees an allocation");

    SnapshotStates.Stream stream = new SnapshotStates.Stream(set);
    int n = stream.snapshots.size();
    long[] ticks = new long[n];
    long[] ages = new long[n];
    byte[][] bytes = new byte[n][];
    for (int i = 0; i < n; ++i) {
      Snapshot s = stream.snapshots.get(i);
      ticks[i] = s.getTick() & 0xFFFFFFFFL;
      ages[i] = s.getBaselineAge() & 0xFFFFFFFFL;
      bytes[i] = s.getEntities().toByteArray();
    }
    SnapshotDecoder decoder = new SnapshotDecoder(stream.spec);
    // Warm both paths (JIT included), then measure a round of each.
    int round = 0;
    for (int warm = 0; warm < WARM_ROUNDS; ++warm) {
      assertEquals(n, decodeRound(decoder, round++, ticks, ages, bytes));
      List<Snapshot> messages = messagesOfRound(stream.snapshots, round++);
      assertEquals(n, decodeMessages(decoder, messages));
    }
    // The least of a few rounds: a JIT event (a deoptimisation re-creating objects escape
    // analysis had removed) allocates once, not per snapshot; a per-snapshot allocation shows
    // in every round.
    long[] accepted = new long[1];
    long allocated = Long.MAX_VALUE;
    for (int measured = 0; measured < MEASURED_ROUNDS; ++measured) {
      int rawRound = round++;
      allocated = Math.min(allocated,
          measure(() -> accepted[0] = decodeRound(decoder, rawRound, ticks, ages, bytes)));
      assertEquals(n, accepted[0], "every snapshot accepted");
    }
    assertEquals(0, allocated, set + ": bytes allocated decoding " + n + " warm snapshots");

    allocated = Long.MAX_VALUE;
    for (int measured = 0; measured < MEASURED_ROUNDS; ++measured) {
      List<Snapshot> messages = messagesOfRound(stream.snapshots, round++);
      allocated =
          Math.min(allocated, measure(() -> accepted[0] = decodeMessages(decoder, messages)));
      assertEquals(n, accepted[0]);
    }
    assertEquals(0, allocated, set + ": bytes allocated by decode(Snapshot), " + n + " snapshots");
  }

  /** The stream's messages with their ticks moved on by {@code round} rounds. */
  private static List<Snapshot> messagesOfRound(List<Snapshot> snapshots, int round) {
    List<Snapshot> messages = new ArrayList<>(snapshots.size());
    long offset = round * ROUND_TICKS;
    for (Snapshot s : snapshots) {
      messages.add(s.toBuilder().setTick((int) ((s.getTick() & 0xFFFFFFFFL) + offset)).build());
    }
    return messages;
  }

  private static int decodeMessages(SnapshotDecoder decoder, List<Snapshot> messages) {
    int accepted = 0;
    for (int i = 0; i < messages.size(); ++i) {
      if (decoder.decode(messages.get(i))) ++accepted;
    }
    return accepted;
  }

  private static int decodeRound(
      SnapshotDecoder decoder, int round, long[] ticks, long[] ages, byte[][] bytes) {
    int accepted = 0;
    long offset = round * ROUND_TICKS;
    for (int i = 0; i < ticks.length; ++i) {
      if (decoder.decode(ticks[i] + offset, ages[i], bytes[i], 0, bytes[i].length)) ++accepted;
    }
    return accepted;
  }

  static volatile byte[] sink;

  /** Bytes allocated on this thread by {@code work}, less what the measuring itself costs. */
  private long measure(Runnable work) {
    long self = Thread.currentThread().getId();
    long before = threads.getThreadAllocatedBytes(self);
    long after = threads.getThreadAllocatedBytes(self);
    long overhead = after - before;
    before = threads.getThreadAllocatedBytes(self);
    work.run();
    after = threads.getThreadAllocatedBytes(self);
    return after - before - overhead;
  }
}
