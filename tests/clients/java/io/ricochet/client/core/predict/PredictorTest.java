package io.ricochet.client.core.predict;

import static org.junit.jupiter.api.Assertions.assertArrayEquals;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;

import io.ricochet.client.core.snapshot.QuantizationSpec;
import org.junit.jupiter.api.Test;

/** Reconciliation: re-seed from the server, replay exactly the inputs it has not applied. */
class PredictorTest {
  private static final int RATE = 60;
  private static final float DT = 1f / RATE;
  private static final CollisionWorld FLOOR =
      Worlds.of(Worlds.empty().addPlanes(Worlds.plane(0, 1, 0, 0)));

  private static final float[] REST = {0, 0.4f, 0};
  private static final float[] STILL = {0, 0, 0};

  /** What input `seq` of the test's script does: forward, turning, jumping at 5. */
  private static void applyScripted(Predictor predictor, long seq) {
    predictor.apply(seq, (int) (seq % 3) * 40, 127, 0.05f * seq, seq == 5 ? 1 : 0);
  }

  /** The same inputs stepped by hand on a fresh sphere from `from` (SphereWorld and the rules). */
  private static float[] stepByHand(float[] from, float[] velocityFrom, long first, long last) {
    SphereWorld sphere = new SphereWorld(FLOOR);
    sphere.seed(from, velocityFrom);
    float[] wish = new float[4];
    float[] v = new float[3];
    for (long seq = first; seq <= last; ++seq) {
      CharacterMotion.wish((int) (seq % 3) * 40, 127, 0.05f * seq, wish);
      boolean grounded = sphere.grounded();
      sphere.velocity(v);
      CharacterMotion.velocity(FLOOR.movement, wish, seq == 5, grounded, DT, v);
      sphere.setVelocity(v);
      sphere.step(DT);
    }
    float[] p = new float[3];
    sphere.position(p);
    return p;
  }

  @Test
  void aSnapshotReplaysExactlyTheInputsAfterTheAcknowledgedOne() {
    Predictor predictor = new Predictor(FLOOR, QuantizationSpec.defaults(), RATE);
    for (long seq = 1; seq <= 10; ++seq) applyScripted(predictor, seq);
    assertFalse(predictor.active()); // nothing seen yet: nothing predicted
    predictor.reconcile(101, true, REST, STILL, 6);
    assertTrue(predictor.active());
    assertEquals(4, predictor.replayed()); // 7, 8, 9, 10
    float[] p = new float[3];
    float[] v = new float[3];
    predictor.predicted(p, v);
    assertArrayEquals(stepByHand(REST, STILL, 7, 10), p, 0f);

    applyScripted(predictor, 11);
    predictor.predicted(p, v);
    assertArrayEquals(stepByHand(REST, STILL, 7, 11), p, 0f);
    assertEquals(1, predictor.resets()); // the first snapshot seeds, it is not an error
  }

  @Test
  void aServerThatAgreesGivesZeroErrorAndOneThatDoesNotGivesTheDistance() {
    QuantizationSpec spec = QuantizationSpec.defaults();
    Predictor predictor = new Predictor(FLOOR, spec, RATE);
    predictor.reconcile(102, true, REST, STILL, 0);
    for (long seq = 1; seq <= 10; ++seq) applyScripted(predictor, seq);
    // the server applied 1..4 from the same state: it is where the prediction was after 4
    float[] at4 = stepByHand(REST, STILL, 1, 4);
    float[] onGrid = new float[3];
    for (int axis = 0; axis < 3; ++axis) {
      double steps = ((double) at4[axis] - spec.boundsMinM(axis)) / spec.positionStepM();
      onGrid[axis] = spec.positionM((int) Math.round(steps), axis);
    }
    predictor.reconcile(103, true, onGrid, STILL, 4);
    assertEquals(6, predictor.replayed());
    double[] summary = new double[3];
    predictor.errors().summarise(summary);
    assertEquals(0.0, summary[2], 0.0);

    // the server says input 8 left the player 0.3 m to the side of the prediction
    float[] predicted8 = new float[3];
    predictor.inputs().predicted(8, predicted8);
    float[] moved = new float[3];
    for (int axis = 0; axis < 3; ++axis) {
      double steps = ((double) predicted8[axis] - spec.boundsMinM(axis)) / spec.positionStepM();
      moved[axis] = spec.positionM((int) Math.round(steps), axis);
    }
    moved[0] += 0.3f;
    predictor.reconcile(104, true, moved, STILL, 8);
    predictor.errors().summarise(summary);
    assertEquals(0.3, summary[2], 0.002);
    assertEquals(1, predictor.corrections());
  }

  @Test
  void aDeadOwnPlayerIsNotPredictedAndItsRespawnIsAResetNotAnError() {
    Predictor predictor = new Predictor(FLOOR, QuantizationSpec.defaults(), RATE);
    predictor.reconcile(105, true, REST, STILL, 0);
    applyScripted(predictor, 1);
    predictor.reconcile(106, false, REST, STILL, 1);
    assertFalse(predictor.active());
    applyScripted(predictor, 2);
    predictor.reconcile(107, true, new float[] {20, 0.4f, 20}, STILL, 2);
    assertEquals(2, predictor.resets());
    assertEquals(0, predictor.errors().count());
  }

  @Test
  void inputsTheServerRepeatedOrSkippedAreCountedFromTheAcknowledgements() {
    Predictor predictor = new Predictor(FLOOR, QuantizationSpec.defaults(), RATE);
    for (long seq = 1; seq <= 12; ++seq) applyScripted(predictor, seq);
    predictor.reconcile(10, true, REST, STILL, 5);
    predictor.reconcile(11, true, REST, STILL, 6); // in order
    assertEquals(0, predictor.inputsOffTick());
    predictor.reconcile(12, true, REST, STILL, 6); // 6 repeated
    assertEquals(1, predictor.inputsOffTick());
    predictor.reconcile(13, true, REST, STILL, 9); // 7 and 8 skipped (or 6 repeated, then a burst)
    assertEquals(3, predictor.inputsOffTick());
    predictor.reconcile(15, true, REST, STILL, 11); // a snapshot lost, inputs in order
    assertEquals(3, predictor.inputsOffTick());
  }

  @Test
  void theErrorWindowGivesNearestRankPercentiles() {
    ErrorWindow window = new ErrorWindow();
    for (int i = 1; i <= 200; ++i) window.add(i / 1000.0);
    double[] out = new double[3];
    window.summarise(out);
    assertEquals(0.100, out[0], 1e-12); // rank ceil(0.5 * 200) = 100
    assertEquals(0.198, out[1], 1e-12); // rank ceil(0.99 * 200) = 198
    assertEquals(0.200, out[2], 1e-12);
    assertEquals(0, window.count()); // a new period
  }
}
