package io.ricochet.client.core.snapshot;

import static org.junit.jupiter.api.Assertions.assertArrayEquals;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;

import io.ricochet.client.testing.Hex;
import io.ricochet.client.testing.Vectors;
import io.ricochet.wire.SnapshotProto.Snapshot;
import java.util.EnumMap;
import java.util.Map;
import org.junit.jupiter.params.ParameterizedTest;
import org.junit.jupiter.params.provider.ValueSource;

/**
 * tests/vectors/snapshots_*.txt, written by the C++ encoder and decoder: the Java decoder reads
 * every snapshot to exactly the C++ decoder's state (hash every tick, every field every 50th,
 * dequantised floats bit for bit), acknowledges the same ticks, and refuses every corruption the
 * C++ decoder refuses with the same reason, unchanged by it.
 */
class SnapshotVectorsTest {
  @ParameterizedTest
  @ValueSource(strings = {"snapshots_spheres901", "snapshots_players64"})
  void theJavaDecoderReadsTheCppStreamToTheCppStatesAtEveryTick(String set) throws Exception {
    SnapshotStates.Stream stream = new SnapshotStates.Stream(set);
    SnapshotDecoder decoder = new SnapshotDecoder(stream.spec);
    SnapshotView view = decoder.view();
    Map<SnapshotRejection, Long> refusedBy = new EnumMap<>(SnapshotRejection.class);
    int snapshots = 0;
    int states = 0;
    int fullStates = 0;
    int refusals = 0;
    byte[] hash = SnapshotStates.fnv1a64(new byte[0]);
    for (Vectors.Record record : stream.records) {
      String where = set + " " + record;
      switch (record.kind) {
        case "snapshot": {
          Snapshot snapshot = Snapshot.parseFrom(record.bytes("bytes"));
          assertEquals(record.number("tick"), snapshot.getTick() & 0xFFFFFFFFL, where);
          assertEquals(record.number("baseline_age"), snapshot.getBaselineAge() & 0xFFFFFFFFL);
          assertTrue(decoder.decode(snapshot), where + " refused: " + decoder.lastRejection());
          assertEquals(record.number("ack"), decoder.newestTick(), where);
          assertEquals(record.number("tick"), view.tick(), where);
          hash = SnapshotStates.fnv1a64(SnapshotStates.canonicalBytes(view));
          ++snapshots;
          break;
        }
        case "state":
          assertEquals(record.number("tick"), view.tick(), where);
          assertEquals(record.number("count"), view.count(), where);
          assertEquals(record.word("hash"), Hex.encode(hash), where);
          ++states;
          break;
        case "entities":
          assertEquals(record.number("tick"), view.tick(), where);
          assertArrayEquals(record.bytes("bytes"), SnapshotStates.canonicalBytes(view), where);
          assertEquals(record.word("floats"),
              Hex.encode(SnapshotStates.fnv1a64(SnapshotStates.dequantizedBytes(view))), where);
          ++fullStates;
          break;
        case "refusal": {
          long newest = decoder.newestTick();
          long accepted = decoder.accepted();
          SnapshotRejection expected = reasonNamed(record.word("reason"));
          assertFalse(decoder.decode(Snapshot.parseFrom(record.bytes("bytes"))), where);
          assertEquals(expected, decoder.lastRejection(), where);
          assertEquals(newest, decoder.newestTick(), where);
          assertEquals(accepted, decoder.accepted(), where);
          assertEquals(newest, view.tick(), where);
          assertArrayEquals(hash, SnapshotStates.fnv1a64(SnapshotStates.canonicalBytes(view)),
              where + ": a refusal changed the state");
          refusedBy.merge(expected, 1L, Long::sum);
          ++refusals;
          break;
        }
        default:
          break;
      }
    }
    assertTrue(snapshots >= 200, set + ": " + snapshots + " snapshots");
    assertEquals(snapshots, states);
    assertTrue(fullStates >= 5, set + ": " + fullStates + " full states");
    assertTrue(refusals >= 50, set + ": " + refusals + " refusals");
    assertEquals(snapshots, decoder.accepted());
    for (Map.Entry<SnapshotRejection, Long> entry : refusedBy.entrySet()) {
      assertEquals((long) entry.getValue(), decoder.rejections(entry.getKey()), set);
    }
  }

  @ParameterizedTest
  @ValueSource(strings = {"snapshots_spheres901", "snapshots_players64"})
  void theStreamsUseOlderBaselinesAndRestartsAsWellAsTheUsualAge(String set) throws Exception {
    SnapshotStates.Stream stream = new SnapshotStates.Stream(set);
    int restarts = 0;
    int older = 0;
    for (Snapshot snapshot : stream.snapshots) {
      if (snapshot.getBaselineAge() == 0) ++restarts;
      if (snapshot.getBaselineAge() > 7) ++older;
    }
    assertTrue(restarts >= 1, set);
    assertTrue(older >= 3, set + ": " + older + " snapshots against baselines older than 7 ticks");
  }

  static SnapshotRejection reasonNamed(String name) {
    for (SnapshotRejection reason : SnapshotRejection.values()) {
      if (reason.counterName().equals(name)) return reason;
    }
    throw new IllegalArgumentException("no rejection named " + name);
  }
}
