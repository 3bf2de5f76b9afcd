package io.ricochet.client.core.predict;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertNotNull;
import static org.junit.jupiter.api.Assertions.assertNull;
import static org.junit.jupiter.api.Assertions.assertTrue;
import static org.junit.jupiter.api.Assertions.fail;

import io.ricochet.client.core.snapshot.QuantizationSpec;
import io.ricochet.client.testing.Vectors;
import java.io.IOException;
import java.util.List;
import java.util.Locale;
import org.junit.jupiter.params.ParameterizedTest;
import org.junit.jupiter.params.provider.ValueSource;

/**
 * The movement vectors (tests/vectors/movement_MAP.txt, tools/vectors/movement_vectors.cpp): a
 * lone player in each sample map the server ships, driven by scripted inputs (running, turning,
 * strafing, jumping, into walls, boxes, rotated boxes, ramps, along mesh edges, off ledges, into a
 * pit), with the state the match's own movement step computes after every tick. The Java
 * prediction runs the same inputs free, from the spawn alone, on the collision world the join
 * reply carries, and must agree at every tick BIT FOR BIT: the ground test, the position and the
 * velocity. Both ends compute in IEEE single precision with the same operations in the same order
 * (the C++ is built with -ffp-contract=off), so no tolerance is needed; one differing bit at one
 * tick fails with the tick, the inputs and both states.
 *
 * <p>Each run is checked twice: through the building blocks a predicting client is made of
 * ({@link CharacterMotion}, {@link SphereWorld}: the ground test is compared there) and through
 * {@link Predictor} itself, seeded by a snapshot at the spawn and fed one input per tick.
 */
class MovementVectorsTest {
  private static final int MIN_TICKS_PER_MAP = 900;

  /** One scripted run of a file: its start and its tick records. */
  private static final class Run {
    final String name;
    final float[] startM;
    final List<Vectors.Record> ticks = new java.util.ArrayList<>();

    Run(String name, float[] startM) {
      this.name = name;
      this.startM = startM;
    }
  }

  @ParameterizedTest
  @ValueSource(strings = {"arena", "foundry"})
  void everyTickOfEveryRunIsTheMatchsBitForBit(String map) throws IOException {
    List<Vectors.Record> records = Vectors.read("movement_" + map);
    Vectors.Record header = records.get(0);
    assertEquals("world", header.kind);
    assertEquals(map, header.word("map"));
    CollisionWorld world = CollisionWorld.parse(header.bytes("bytes"));
    assertNull(world.refusal(), "the join reply's world of " + map + " is refused");
    int tickRateHz = (int) header.number("tick_hz");
    List<Run> runs = runsOf(records);
    assertTrue(runs.size() >= 4, map + " has " + runs.size() + " runs");
    int ticks = 0;
    StringBuilder differences = new StringBuilder(); // each run's first, all runs checked
    for (Run run : runs) {
      ticks += run.ticks.size();
      try {
        checkBuildingBlocks(world, tickRateHz, run);
        checkPredictor(world, tickRateHz, run);
      } catch (AssertionError difference) {
        differences.append(difference.getMessage()).append('\n');
      }
    }
    assertTrue(ticks >= MIN_TICKS_PER_MAP, map + " has " + ticks + " ticks");
    if (differences.length() > 0)
      fail("the Java prediction differs from the match's movement:\n" + differences);
  }

  private static List<Run> runsOf(List<Vectors.Record> records) {
    List<Run> runs = new java.util.ArrayList<>();
    for (Vectors.Record record : records.subList(1, records.size())) {
      if (record.kind.equals("run")) {
        runs.add(new Run(record.word("name"), floats(record.word("position"))));
      } else if (record.kind.equals("tick")) {
        Run run = runs.get(runs.size() - 1);
        assertEquals(run.name, record.word("run"), "line " + record.line);
        assertEquals(run.ticks.size() + 1, record.number("t"), "line " + record.line);
        run.ticks.add(record);
      } else {
        fail("unknown record " + record);
      }
    }
    return runs;
  }

  /**
   * The run through CharacterMotion and SphereWorld, as Predictor steps: ground, velocity, step.
   */
  private static void checkBuildingBlocks(CollisionWorld world, int tickRateHz, Run run) {
    SphereWorld sphere = new SphereWorld(world);
    sphere.seed(run.startM, new float[3]);
    MovementRules rules = world.movement();
    float tickS = 1.0f / tickRateHz;
    float[] wish = new float[4];
    float[] velocity = new float[3];
    float[] position = new float[3];
    for (Vectors.Record tick : run.ticks) {
      CharacterMotion.wish(
          (int) tick.number("right"), (int) tick.number("forward"), yaw(tick), wish);
      boolean grounded = sphere.grounded();
      if (grounded != (tick.number("grounded") == 1)) {
        sphere.position(position);
        fail(describe(run, tick, "ground test " + grounded, position, null));
      }
      sphere.velocity(velocity);
      CharacterMotion.velocity(
          rules, wish, (tick.number("buttons") & 1) != 0, grounded, tickS, velocity);
      sphere.setVelocity(velocity);
      sphere.step(tickS);
      sphere.position(position);
      sphere.velocity(velocity);
      expectBits(run, tick, position, velocity);
    }
  }

  /** The run through Predictor: a snapshot at the spawn (no input yet), then one input a tick. */
  private static void checkPredictor(CollisionWorld world, int tickRateHz, Run run) {
    Predictor predictor = new Predictor(world, QuantizationSpec.defaults(), tickRateHz);
    predictor.reconcile(1, true, run.startM, new float[3], 0);
    assertTrue(predictor.active());
    float[] position = new float[3];
    float[] velocity = new float[3];
    for (Vectors.Record tick : run.ticks) {
      predictor.apply(tick.number("t"), (int) tick.number("right"), (int) tick.number("forward"),
          yaw(tick), (int) tick.number("buttons"));
      predictor.predicted(position, velocity);
      expectBits(run, tick, position, velocity);
    }
    assertEquals(run.ticks.size(), predictor.newestInput());
  }

  private static void expectBits(
      Run run, Vectors.Record tick, float[] positionM, float[] velocityMps) {
    float[] position = floats(tick.word("position"));
    float[] velocity = floats(tick.word("velocity"));
    for (int axis = 0; axis < 3; ++axis) {
      if (Float.floatToRawIntBits(positionM[axis]) != Float.floatToRawIntBits(position[axis])
          || Float.floatToRawIntBits(velocityMps[axis])
              != Float.floatToRawIntBits(velocity[axis])) {
        fail(describe(run, tick, "state", positionM, velocityMps));
      }
    }
  }

  private static String describe(
      Run run, Vectors.Record tick, String what, float[] positionM, float[] velocityMps) {
    StringBuilder out = new StringBuilder();
    out.append(String.format(Locale.ROOT,
        "run %s tick %d (line %d: right %d forward %d yaw %.6f buttons %d): the %s differs;%n",
        run.name, tick.number("t"), tick.line, tick.number("right"), tick.number("forward"),
        yaw(tick), tick.number("buttons"), what));
    out.append("  C++:  grounded ").append(tick.number("grounded"));
    out.append(" position ").append(text(floats(tick.word("position"))));
    out.append(" velocity ").append(text(floats(tick.word("velocity")))).append('\n');
    out.append("  Java: position ").append(text(positionM));
    if (velocityMps != null) out.append(" velocity ").append(text(velocityMps));
    return out.toString();
  }

  private static String text(float[] v) {
    return String.format(Locale.ROOT, "(%.9g, %.9g, %.9g)", v[0], v[1], v[2]);
  }

  private static float yaw(Vectors.Record tick) {
    float[] one = new float[1];
    decode(tick.word("yaw"), one);
    return one[0];
  }

  /** Big-endian IEEE bits, 8 hex digits per float. */
  private static float[] floats(String hex) {
    assertNotNull(hex);
    assertEquals(24, hex.length(), "three floats: " + hex);
    float[] out = new float[3];
    decode(hex, out);
    return out;
  }

  private static void decode(String hex, float[] out) {
    assertEquals(8 * out.length, hex.length(), hex);
    for (int k = 0; k < out.length; ++k) {
      out[k] = Float.intBitsToFloat((int) Long.parseLong(hex.substring(8 * k, 8 * k + 8), 16));
    }
  }
}
