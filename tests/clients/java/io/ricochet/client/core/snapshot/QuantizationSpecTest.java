package io.ricochet.client.core.snapshot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertNotNull;
import static org.junit.jupiter.api.Assertions.assertNull;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import io.ricochet.wire.SnapshotProto.Quantization;
import org.junit.jupiter.api.Test;

/** The spec from JoinMatchReply.quantization (PROTOCOL.md, Snapshots §2): checks and integers. */
class QuantizationSpecTest {
  private static Quantization.Builder defaults() {
    return QuantizationSpec.defaults().toWire().toBuilder();
  }

  @Test
  void theDefaultsDeriveTheProtocolsIntegers() {
    QuantizationSpec spec = QuantizationSpec.fromWire(defaults().build());
    assertNotNull(spec);
    assertEquals(128001, spec.positionSteps(0));
    assertEquals(64001, spec.positionSteps(1));
    assertEquals(17, spec.positionBits(0));
    assertEquals(16, spec.positionBits(1));
    assertEquals(6400, spec.velocityLimit());
    assertEquals(14, spec.velocityBits());
    assertEquals(255, spec.orientationLimit());
    assertEquals(10923, spec.predictionScale()); // llround(65536 * 0.01 / 60 / 0.001)
  }

  @Test
  void theFloatNearestAMillimetreIsAcceptedAndAnythingCoarserRefused() {
    assertNotNull(QuantizationSpec.fromWire(defaults().setPositionStepM(0.001f).build()));
    Quantization coarse = defaults().setPositionStepM(Math.nextUp(0.001f)).build();
    assertNull(QuantizationSpec.fromWire(coarse));
    assertTrue(QuantizationSpec.problemWith(coarse).startsWith("position_step_m"));
  }

  @Test
  void unusableSpecsAreRefusedWithTheFieldNamed() {
    assertTrue(QuantizationSpec.problemWith(defaults().clearBoundsMinM().build())
                   .startsWith("quantization bounds"));
    assertTrue(QuantizationSpec.problemWith(defaults().setBoundsMaxM(1, -20f).build())
                   .startsWith("bounds.y"));
    assertTrue(QuantizationSpec.problemWith(defaults().setBoundsMinM(2, Float.NaN).build())
                   .startsWith("bounds.z"));
    assertTrue(QuantizationSpec.problemWith(defaults().setOrientationBits(17).build())
                   .contains("orientation_bits"));
    assertTrue(QuantizationSpec.problemWith(defaults().setOrientationBits(0x80000004).build())
                   .contains("orientation_bits"));
    assertTrue(QuantizationSpec.problemWith(defaults().setOrientationBits(3).build())
                   .contains("orientation_bits"));
    assertTrue(QuantizationSpec.problemWith(defaults().setVelocityStepMps(0f).build())
                   .startsWith("velocity_step_mps"));
    assertTrue(QuantizationSpec.problemWith(defaults().setMaxSpeedMps(0.001f).build())
                   .startsWith("max_speed_mps"));
    assertTrue(QuantizationSpec.problemWith(defaults().setTickS(0f).build()).startsWith("tick_s"));
    assertTrue(QuantizationSpec.problemWith(defaults().setVelocityStepMps(1f).setTickS(1f).build())
                   .contains("<= 128"));
    Quantization huge = defaults().setBoundsMinM(0, -1e7f).setBoundsMaxM(0, 1e7f).build();
    assertTrue(QuantizationSpec.problemWith(huge).contains("2^31"));
    assertEquals("", QuantizationSpec.problemWith(defaults().build()));
  }

  @Test
  void specsTheAppBuildsAreCheckedToo() {
    assertThrows(IllegalArgumentException.class,
        ()
            -> QuantizationSpec.of(
                new float[] {0, 0, 0}, new float[] {1, 1, 1}, 0.01f, 0.01f, 64f, 9, 1f / 60));
    QuantizationSpec spec = QuantizationSpec.of(
        new float[] {-1, -2, -3}, new float[] {1, 2, 3}, 0.0005f, 0.02f, 10f, 12, 1f / 30);
    assertEquals(4001, spec.positionSteps(0));
    assertEquals(500, spec.velocityLimit());
    assertEquals(2047, spec.orientationLimit());
    assertEquals(spec.toWire(), QuantizationSpec.fromWire(spec.toWire()).toWire());
  }
}
