package io.ricochet.client.core.snapshot;

import static org.junit.jupiter.api.Assertions.assertArrayEquals;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertNotNull;
import static org.junit.jupiter.api.Assertions.assertTrue;

import io.ricochet.wire.SnapshotProto.Snapshot;
import java.util.Arrays;
import java.util.EnumSet;
import java.util.List;
import java.util.Random;
import java.util.Set;
import org.junit.jupiter.params.ParameterizedTest;
import org.junit.jupiter.params.provider.ValueSource;

/**
 * Untrusted bytes: every snapshot of the vector streams, corrupted thousands of ways (bit flips,
 * truncations, random tails, random bytes, wrong ages), never throws out of decode; a refusal
 * leaves the state exactly as it was, and the real snapshot then decodes. A corruption that is
 * still a valid stream is accepted (nothing in the stream can tell), after which the decoder is
 * rebuilt from the stream so far.
 */
class SnapshotCorruptionTest {
  private static final int CORRUPTIONS_PER_SNAPSHOT = 8;

  @ParameterizedTest
  @ValueSource(strings = {"snapshots_spheres901", "snapshots_players64"})
  void corruptedSnapshotsAreRefusedOrHarmlessAndNeverThrow(String set) throws Exception {
    SnapshotStates.Stream stream = new SnapshotStates.Stream(set);
    List<Snapshot> snapshots = stream.snapshots;
    Random random = new Random(30);
    SnapshotDecoder decoder = new SnapshotDecoder(stream.spec);
    Set<SnapshotRejection> seen = EnumSet.noneOf(SnapshotRejection.class);
    int accepted = 0;
    for (int i = 0; i < snapshots.size(); ++i) {
      Snapshot real = snapshots.get(i);
      byte[] bytes = real.getEntities().toByteArray();
      long tick = real.getTick() & 0xFFFFFFFFL;
      long age = real.getBaselineAge() & 0xFFFFFFFFL;
      for (int c = 0; c < CORRUPTIONS_PER_SNAPSHOT; ++c) {
        byte[] corrupt = corrupt(bytes, random);
        long corruptAge = random.nextInt(8) == 0 ? random.nextInt(80) : age;
        byte[] before = SnapshotStates.canonicalBytes(decoder.view());
        long newest = decoder.newestTick();
        boolean ok = decoder.decode(tick, corruptAge, corrupt, 0, corrupt.length);
        if (ok) {
          // A corruption that still makes a valid stream: start again from the C++ states.
          ++accepted;
          decoder = replayed(stream, snapshots, i);
          continue;
        }
        assertNotNull(decoder.lastRejection());
        seen.add(decoder.lastRejection());
        assertEquals(newest, decoder.newestTick());
        assertArrayEquals(before, SnapshotStates.canonicalBytes(decoder.view()),
            set + " tick " + tick + ": a refusal changed the state");
      }
      assertTrue(decoder.decode(real), set + " tick " + tick + ": " + decoder.lastRejection());
    }
    assertTrue(
        seen.containsAll(EnumSet.of(SnapshotRejection.TRUNCATED, SnapshotRejection.TRAILING_BITS,
            SnapshotRejection.VALUE_OUT_OF_RANGE, SnapshotRejection.UNKNOWN_BASELINE)),
        set + ": refused for " + seen);
    // The stream has no checksum (the packet's AEAD guards it): a flipped bit inside a value is
    // often another valid value. Most corruptions must still be caught.
    int corruptions = snapshots.size() * CORRUPTIONS_PER_SNAPSHOT;
    assertTrue(accepted < corruptions / 4,
        set + ": " + accepted + " of " + corruptions + " corruptions accepted");
  }

  /** A decoder that has read snapshots[0, end) (which the vectors test checks). */
  private static SnapshotDecoder replayed(
      SnapshotStates.Stream stream, List<Snapshot> snapshots, int end) {
    SnapshotDecoder decoder = new SnapshotDecoder(stream.spec);
    for (int k = 0; k < end; ++k) assertTrue(decoder.decode(snapshots.get(k)));
    return decoder;
  }

  private static byte[] corrupt(byte[] bytes, Random random) {
    switch (random.nextInt(5)) {
      case 0: { // flip 1..3 bits
        byte[] out = bytes.clone();
        if (out.length == 0) return new byte[] {(byte) random.nextInt(256)};
        int flips = 1 + random.nextInt(3);
        for (int f = 0; f < flips; ++f) {
          int bit = random.nextInt(out.length * 8);
          out[bit / 8] ^= (byte) (0x80 >>> (bit % 8));
        }
        return out;
      }
      case 1: // cut short
        return Arrays.copyOf(bytes, bytes.length == 0 ? 0 : random.nextInt(bytes.length));
      case 2: { // a random tail
        byte[] out = Arrays.copyOf(bytes, bytes.length + 1 + random.nextInt(8));
        for (int k = bytes.length; k < out.length; ++k) out[k] = (byte) random.nextInt(256);
        return out;
      }
      case 3: { // random bytes from some point on
        byte[] out = bytes.clone();
        for (int k = out.length == 0 ? 0 : random.nextInt(out.length); k < out.length; ++k) {
          out[k] = (byte) random.nextInt(256);
        }
        return out;
      }
      default: { // noise of any length up to the limit and beyond
        byte[] out = new byte[random.nextInt(SnapshotDecoder.MAX_STREAM_BYTES + 16)];
        random.nextBytes(out);
        return out;
      }
    }
  }
}
