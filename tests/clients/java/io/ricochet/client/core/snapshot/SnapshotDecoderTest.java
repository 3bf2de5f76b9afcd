package io.ricochet.client.core.snapshot;

import static org.junit.jupiter.api.Assertions.assertArrayEquals;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;

import io.ricochet.client.testing.Hex;
import io.ricochet.wire.SnapshotProto.Snapshot;
import org.junit.jupiter.api.Test;

/**
 * Hand-made snapshots (PROTOCOL.md, Snapshots §4 to §10): new entities, deltas with prediction,
 * and one refusal of each reason, each leaving the decoder as it was.
 *
 * <p>The spec: bounds (-1, -1, -1)..(1, 1, 1) m, 1 mm (2001 steps, 11 bits), 0.01 m/s up to 64
 * m/s (limit 6400, 14 bits), 9 orientation bits (limit 255), 60 Hz (prediction scale 10923).
 */
class SnapshotDecoderTest {
  private static final QuantizationSpec SPEC = QuantizationSpec.of(
      new float[] {-1f, -1f, -1f}, new float[] {1f, 1f, 1f}, 0.001f, 0.01f, 64f, 9, 1.0f / 60);

  /** Tick 1, no baseline: entity 7 moving, turned, flagged; entity 8 at the origin corner. */
  private static byte[] twoNewEntities() {
    StreamWriter out = new StreamWriter();
    out.eg(0, 0); // no removals
    out.eg(2, 0).bits(0, 5); // two additions, id order 0
    out.eg(7, 0); // id 7
    out.bits(1000, 11).bits(1001, 11).bits(2000, 11);
    out.bits(1, 1).bits(6400 + 100, 14).bits(6400 - 5, 14).bits(6400, 14);
    out.bits(1, 1).bits(1, 2).bits(255 + 10, 9).bits(255 - 20, 9).bits(255, 9);
    out.bits(1, 1).bits(0x11, 8);
    out.eg(0, 0); // id 8
    out.bits(0, 33).bits("000"); // at (0, 0, 0), still, identity, no flags
    out.eg(0, 0); // no changes
    return out.bytes();
  }

  private static SnapshotDecoder decoderAtTickOne() {
    SnapshotDecoder decoder = new SnapshotDecoder(SPEC);
    byte[] stream = twoNewEntities();
    assertTrue(decoder.decode(1, 0, stream, 0, stream.length), "tick 1");
    return decoder;
  }

  @Test
  void theProtocolsExampleOfNothingChangedDecodes() throws Exception {
    SnapshotDecoder decoder = new SnapshotDecoder(QuantizationSpec.defaults());
    byte[] empty = Hex.decode("e0");
    assertTrue(decoder.decode(294, 0, empty, 0, 1));
    Snapshot example = Snapshot.parseFrom(Hex.decode("08ac0210061a01e0"));
    assertTrue(decoder.decode(example));
    assertEquals(300, decoder.newestTick());
    assertEquals(300, decoder.view().tick());
    assertEquals(0, decoder.view().count());
    assertEquals(2, decoder.accepted());
  }

  @Test
  void newEntitiesArriveWithEveryFieldAndTheirDequantisedValues() {
    SnapshotView view = decoderAtTickOne().view();
    assertEquals(2, view.count());
    assertEquals(7, view.id(0));
    assertEquals(8, view.id(1));
    assertEquals(1, view.indexOf(8));
    assertEquals(-1, view.indexOf(9));
    assertEquals(1000, view.positionSteps(0, 0));
    assertEquals(1001, view.positionSteps(0, 1));
    assertEquals(2000, view.positionSteps(0, 2));
    assertEquals(100, view.velocitySteps(0, 0));
    assertEquals(-5, view.velocitySteps(0, 1));
    assertEquals(0, view.velocitySteps(0, 2));
    assertEquals(1, view.orientationLargest(0));
    assertEquals(10, view.orientationSteps(0, 0));
    assertEquals(-20, view.orientationSteps(0, 1));
    assertEquals(0, view.orientationSteps(0, 2));
    assertEquals(0x11, view.flags(0));
    assertEquals(EntityFlags.KIND_PLAYER, EntityFlags.kind(view.flags(0)));
    assertTrue(EntityFlags.has(view.flags(0), EntityFlags.DEAD));
    // min + steps * step in double, then float (proto::dequantize).
    assertEquals((float) (-1.0 + 2000 * (double) 0.001f), view.positionM(0, 2));
    assertEquals(1.0f, view.positionM(0, 2), 1e-6f);
    assertEquals(1.0f, view.velocityMps(0, 0), 1e-6f);
    float[] q = new float[4];
    view.orientation(0, q);
    double scale = 1.0 / (1.4142135623730951 * 255);
    assertEquals((float) (10 * scale), q[0], 1e-6f);
    assertEquals(-20 * scale, q[2], 1e-6);
    assertEquals(1.0, q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3], 1e-6);
    assertTrue(q[1] > 0.99f, "y is the largest component");
    assertEquals(-1.0f, view.positionM(1, 0));
    view.orientation(1, q);
    assertArrayEquals(new float[] {0, 0, 0, 1}, q);
    assertEquals(0, view.flags(1));
  }

  @Test
  void aChangedEntityFollowsItsPredictedMotionPlusItsResidual() {
    SnapshotDecoder decoder = decoderAtTickOne();
    StreamWriter out = new StreamWriter();
    out.eg(0, 0).eg(0, 0); // no removals, no additions
    out.eg(1, 0); // one change
    out.bits(0, 5).bits(0, 5).bits(0, 5).bits(0, 5).bits(0, 5).bits(0, 5).bits(0, 5).bits(31, 5);
    out.eg(0, 0); // index 0: entity 7
    out.bits("1"); // the previous mask: velocity and position
    out.seg(2, 0).seg(0, 0).seg(0, 0); // velocity (102, -5, 0)
    out.seg(-1, 0).seg(0, 0).seg(0, 0); // residual
    byte[] stream = out.bytes();
    assertTrue(
        decoder.decode(3, 2, stream, 0, stream.length), "refused: " + decoder.lastRejection());
    // age 2: weights 10923 and 32769; motion = (vb * wb + vn * wn + 2^16) >> 17.
    SnapshotView view = decoder.view();
    assertEquals(102, view.velocitySteps(0, 0));
    assertEquals(1000 + 34 - 1, view.positionSteps(0, 0));
    assertEquals(1001 - 2, view.positionSteps(0, 1)); // floor(-1.17) = -2
    assertEquals(2000, view.positionSteps(0, 2));
    assertEquals(10, view.orientationSteps(0, 0));
    assertEquals(0x11, view.flags(0));
    assertEquals(0, view.positionSteps(1, 0)); // entity 8 as it was
    assertEquals(3, decoder.newestTick());
  }

  @Test
  void maskZeroMovesAnEntityByItsBaselineVelocityAndFlagsReplaceTheFlags() {
    SnapshotDecoder decoder = decoderAtTickOne();
    StreamWriter out = new StreamWriter();
    out.eg(0, 0).eg(0, 0).eg(2, 0);
    for (int k = 0; k < 8; ++k) out.bits(31, 5); // every code 0
    out.bits("0 0000"); // entity 7: mask 0, predicted from (100, -5, 0) over 1 tick
    out.bits("0 0001").bits(0x30, 8); // entity 8: flags only
    byte[] stream = out.bytes();
    assertTrue(
        decoder.decode(2, 1, stream, 0, stream.length), "refused: " + decoder.lastRejection());
    SnapshotView view = decoder.view();
    // age 1: (100 * 0 + 100 * 21846 + 65536) >> 17 = 17; (-5 * 21846 + 65536) >> 17 = -1.
    assertEquals(1000 + 17, view.positionSteps(0, 0));
    assertEquals(1001 - 1, view.positionSteps(0, 1));
    assertEquals(0x30, view.flags(1));
    assertTrue(EntityFlags.has(view.flags(1), EntityFlags.PROTECTED));
  }

  @Test
  void removalsDropBaselineEntitiesByIndex() {
    SnapshotDecoder decoder = decoderAtTickOne();
    byte[] stream = new StreamWriter().eg(1, 0).bits(0, 5).eg(0, 0).eg(0, 0).eg(0, 0).bytes();
    assertTrue(decoder.decode(2, 1, stream, 0, stream.length));
    assertEquals(1, decoder.view().count());
    assertEquals(8, decoder.view().id(0));
  }

  @Test
  void headerRefusals() {
    SnapshotDecoder decoder = decoderAtTickOne();
    byte[] nothing = Hex.decode("e0");
    assertRefused(decoder, SnapshotRejection.STALE, 1, 0, nothing);
    assertRefused(decoder, SnapshotRejection.BASELINE_AFTER_TICK, 5, 6, nothing);
    assertRefused(decoder, SnapshotRejection.UNKNOWN_BASELINE, 5, 2, nothing);
    assertRefused(decoder, SnapshotRejection.OVERSIZED, 2, 1, new byte[1201]);
    Snapshot oversized = Snapshot.newBuilder()
                             .setTick(2)
                             .setBaselineAge(1)
                             .setEntities(com.google.protobuf.ByteString.copyFrom(new byte[1201]))
                             .build();
    assertFalse(decoder.decode(oversized));
    assertEquals(SnapshotRejection.OVERSIZED, decoder.lastRejection());
  }

  @Test
  void streamRefusals() {
    SnapshotDecoder decoder = decoderAtTickOne();
    assertRefused(decoder, SnapshotRejection.TRUNCATED, 2, 1, new byte[0]);
    assertRefused(decoder, SnapshotRejection.TRUNCATED, 2, 1, Hex.decode("c0")); // no change count
    assertRefused(decoder, SnapshotRejection.BAD_CODE, 2, 1, new byte[6]); // 48 zero bits
    // 3 removals of a 2-entity baseline; a removal index 2.
    assertRefused(decoder, SnapshotRejection.REMOVED_OUT_OF_RANGE, 2, 1,
        new StreamWriter().eg(3, 0).eg(0, 0).eg(0, 0).bytes());
    assertRefused(decoder, SnapshotRejection.REMOVED_OUT_OF_RANGE, 2, 1,
        new StreamWriter().eg(1, 0).bits(0, 5).eg(2, 0).eg(0, 0).eg(0, 0).bytes());
    // A new id already held (8), and one of 2^32.
    assertRefused(decoder, SnapshotRejection.ID_OUT_OF_ORDER, 2, 1,
        new StreamWriter().eg(0, 0).eg(1, 0).bits(0, 5).eg(8, 0).bits(0, 36).eg(0, 0).bytes());
    assertRefused(decoder, SnapshotRejection.ID_OUT_OF_ORDER, 2, 1,
        new StreamWriter()
            .eg(0, 0)
            .eg(1, 0)
            .bits(30, 5)
            .eg(1L << 32, 30)
            .bits(0, 36)
            .eg(0, 0)
            .bytes());
    // An addition count beyond the bits left.
    assertRefused(
        decoder, SnapshotRejection.TRUNCATED, 2, 1, new StreamWriter().eg(0, 0).eg(100, 0).bytes());
    // 3 changes of 2 kept entities; a change index 2.
    assertRefused(decoder, SnapshotRejection.CHANGED_OUT_OF_RANGE, 2, 1,
        new StreamWriter().eg(0, 0).eg(0, 0).eg(3, 0).bytes());
    StreamWriter indexTwo = new StreamWriter().eg(0, 0).eg(0, 0).eg(1, 0);
    indexTwo.bits(0, 5); // gaps in EG(0), every other code 0
    for (int k = 1; k < 8; ++k) indexTwo.bits(31, 5);
    assertRefused(
        decoder, SnapshotRejection.CHANGED_OUT_OF_RANGE, 2, 1, indexTwo.eg(2, 0).bits("1").bytes());
    // Entity 8 is still: mask 0 predicts no motion; flags set to what they were.
    StreamWriter empty = new StreamWriter().eg(0, 0).eg(0, 0).eg(1, 0);
    empty.bits(0, 5); // gaps in EG(0), every other code 0
    for (int k = 1; k < 8; ++k) empty.bits(31, 5);
    assertRefused(
        decoder, SnapshotRejection.EMPTY_CHANGE, 2, 1, empty.eg(1, 0).bits("0 0000").bytes());
    StreamWriter sameFlags = new StreamWriter().eg(0, 0).eg(0, 0).eg(1, 0);
    sameFlags.bits(0, 5); // gaps in EG(0), every other code 0
    for (int k = 1; k < 8; ++k) sameFlags.bits(31, 5);
    assertRefused(decoder, SnapshotRejection.EMPTY_CHANGE, 2, 1,
        sameFlags.eg(1, 0).bits("0 0001").bits(0, 8).bytes());
    // A velocity past the limit: entity 7's 100 + 6301 steps.
    StreamWriter fast = new StreamWriter().eg(0, 0).eg(0, 0).eg(1, 0);
    fast.bits(0, 5).bits(20, 5).bits(31, 5).bits(31, 5).bits(31, 5).bits(31, 5).bits(31, 5);
    fast.bits(31, 5);
    assertRefused(decoder, SnapshotRejection.VALUE_OUT_OF_RANGE, 2, 1,
        fast.eg(0, 0).bits("0 1000").seg(6301, 20).bytes());
    // A new entity at position step 2001 of 2001; a component past the limit.
    assertRefused(decoder, SnapshotRejection.VALUE_OUT_OF_RANGE, 2, 1,
        new StreamWriter()
            .eg(0, 0)
            .eg(1, 0)
            .bits(0, 5)
            .eg(9, 0)
            .bits(2001, 11)
            .bits(0, 22)
            .bits("000")
            .eg(0, 0)
            .bytes());
    assertRefused(decoder, SnapshotRejection.VALUE_OUT_OF_RANGE, 2, 1,
        new StreamWriter()
            .eg(0, 0)
            .eg(1, 0)
            .bits(0, 5)
            .eg(9, 0)
            .bits(0, 33)
            .bits("0 1")
            .bits(0, 2)
            .bits(511, 9)
            .bits(255, 9)
            .bits(255, 9)
            .bits("0")
            .eg(0, 0)
            .bytes());
    // Bits after the last field: a whole zero byte, or a 1 in the padding.
    assertRefused(decoder, SnapshotRejection.TRAILING_BITS, 2, 1, Hex.decode("e000"));
    assertRefused(decoder, SnapshotRejection.TRAILING_BITS, 2, 1, Hex.decode("f0"));
  }

  @Test
  void aVelocityOutOfRangeIsReportedBeforeTheFieldsAfterItButOtherValuesAfterTheEntity() {
    SnapshotDecoder decoder = decoderAtTickOne();
    // Velocity and position marked, the stream ending after a velocity past the limit: the
    // velocity is checked first (value_out_of_range, as the C++ decoder).
    StreamWriter fast = new StreamWriter().eg(0, 0).eg(0, 0).eg(1, 0);
    fast.bits(0, 5).bits(20, 5).bits(31, 5).bits(31, 5).bits(0, 5).bits(0, 5).bits(0, 5);
    fast.bits(31, 5);
    assertRefused(decoder, SnapshotRejection.VALUE_OUT_OF_RANGE, 2, 1,
        fast.eg(0, 0).bits("0 1100").seg(6301, 20).bytes());
    // A component past the limit, the stream ending inside the flags after it: the end of the
    // stream is found first (truncated).
    StreamWriter turned = new StreamWriter().eg(0, 0).eg(0, 0).eg(1, 0);
    turned.bits(0, 5);
    for (int k = 1; k < 8; ++k) turned.bits(31, 5);
    byte[] stream = turned.eg(1, 0)
                        .bits("0 0011")
                        .bits("0")
                        .bits(0, 2)
                        .bits(511, 9)
                        .bits(255, 9)
                        .bits(255, 9)
                        .bits(1, 3)
                        .bytes();
    assertRefused(decoder, SnapshotRejection.TRUNCATED, 2, 1, stream);
  }

  @Test
  void aBaselineTheRingHasOverwrittenIsUnknown() {
    SnapshotDecoder decoder = decoderAtTickOne();
    byte[] nothing = Hex.decode("e0");
    assertTrue(decoder.decode(65, 64, nothing, 0, 1), "tick 1 is still held, 64 ticks on");
    assertEquals(2, decoder.view().count());
    assertTrue(decoder.decode(66, 0, nothing, 0, 1));
    // Tick 65 took tick 1's slot (1 mod 64): tick 1 is gone, tick 65 is there.
    assertRefused(decoder, SnapshotRejection.UNKNOWN_BASELINE, 67, 66, nothing);
    assertTrue(decoder.decode(67, 2, nothing, 0, 1));
    assertEquals(2, decoder.view().count());
  }

  @Test
  void theEntityLimitRefusesLargerSets() {
    SnapshotDecoder decoder = new SnapshotDecoder(SPEC, 64, 1);
    byte[] stream = twoNewEntities();
    assertFalse(decoder.decode(1, 0, stream, 0, stream.length));
    assertEquals(SnapshotRejection.TOO_MANY_ENTITIES, decoder.lastRejection());
    assertFalse(decoder.hasSnapshot());
    assertFalse(decoder.view().hasSnapshot());
  }

  @Test
  void everyRefusalIsCountedByReason() {
    SnapshotDecoder decoder = decoderAtTickOne();
    byte[] nothing = Hex.decode("e0");
    assertRefused(decoder, SnapshotRejection.STALE, 1, 0, nothing);
    assertRefused(decoder, SnapshotRejection.STALE, 0, 0, nothing);
    assertRefused(decoder, SnapshotRejection.TRAILING_BITS, 2, 1, Hex.decode("f0"));
    assertEquals(2, decoder.rejections(SnapshotRejection.STALE));
    assertEquals(1, decoder.rejections(SnapshotRejection.TRAILING_BITS));
    assertEquals(0, decoder.rejections(SnapshotRejection.BAD_CODE));
    assertEquals(1, decoder.accepted());
    assertTrue(decoder.decode(2, 1, nothing, 0, 1), "still decodes after refusals");
  }

  /** Refused with {@code reason}, and the decoder exactly as before. */
  private static void assertRefused(
      SnapshotDecoder decoder, SnapshotRejection reason, long tick, long age, byte[] stream) {
    SnapshotView view = decoder.view();
    byte[] before = SnapshotStates.canonicalBytes(view);
    long newest = decoder.newestTick();
    long count = decoder.rejections(reason);
    String what = reason + " at tick " + tick + " age " + age + ": " + Hex.encode(stream);
    assertFalse(decoder.decode(tick, age, stream, 0, stream.length), what);
    assertEquals(reason, decoder.lastRejection(), what);
    assertEquals(count + 1, decoder.rejections(reason), what);
    assertEquals(newest, decoder.newestTick(), what);
    assertEquals(newest, view.tick(), what);
    assertArrayEquals(before, SnapshotStates.canonicalBytes(view), what);
  }
}
