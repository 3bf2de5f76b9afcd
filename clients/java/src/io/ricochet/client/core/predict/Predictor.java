package io.ricochet.client.core.predict;

import io.ricochet.client.core.snapshot.QuantizationSpec;

/**
 * Prediction and reconciliation of the own player (PROTOCOL.md Prediction and reconciliation),
 * sans-IO: a {@link SphereWorld} with the match's static shapes and the own sphere. Each own input
 * moves it at once (the movement rules, then one physics step of the tick); on each snapshot the
 * own entity's state at that tick re-seeds it and the inputs after {@code last_input_sequence} are
 * replayed from the {@link InputRing}.
 *
 * <p>Prediction error: for the newest input a snapshot acknowledges, the distance between where
 * the input was predicted to leave the sphere (on the snapshot's position grid) and where the
 * server says it is. While the own entity is dead, absent or away nothing is predicted; the first
 * snapshot after, and any gap over {@link #RESET_DISTANCE_M}, re-seed it and count a reset instead
 * of an error (as the C++ bot's predictor). Allocation-free once warm; not thread-safe.
 */
public final class Predictor {
  /** A larger gap between prediction and server is a teleport (a reset), not an error, m. */
  public static final double RESET_DISTANCE_M = 3.0;

  private final SphereWorld sphere;
  private final MovementRules rules;
  private final QuantizationSpec spec;
  private final float tickS;
  private final InputRing inputs = new InputRing();
  private final ErrorWindow errors = new ErrorWindow();
  private final float[] wish = new float[4];
  private final float[] velocity = new float[3];
  private final float[] position = new float[3];
  private final float[] predicted = new float[3];
  private boolean active;
  private long predictedFrom = Long.MAX_VALUE; // the oldest input with a prediction
  private long measuredUpTo;
  private long resets;
  private long corrections;
  private long replayed;
  private long offTick;
  private long previousTick = -1;
  private long previousAcknowledged;

  /** A predictor in {@code world} (not refused) for a match of {@code tickRateHz}. */
  public Predictor(CollisionWorld world, QuantizationSpec spec, int tickRateHz) {
    this.sphere = new SphereWorld(world);
    this.rules = world.movement;
    this.spec = spec;
    this.tickS = 1.0f / tickRateHz;
  }

  /**
   * One own input, sent with sequence {@code seq}: kept for replays and, while predicting,
   * applied at once. {@code buttons} the wire's bits (bit 0 jump).
   */
  public void apply(long seq, int moveRight, int moveForward, float yawRad, int buttons) {
    inputs.push(seq, moveRight, moveForward, yawRad, (buttons & 1) != 0);
    if (!active) return;
    step(seq);
    if (predictedFrom == Long.MAX_VALUE) predictedFrom = seq;
  }

  /**
   * A decoded snapshot of server tick {@code tick}: {@code alive} whether the own entity is in it
   * as a living, connected player; its position (m) and velocity (m/s) as decoded; {@code
   * acknowledged} the payload's {@code last_input_sequence}.
   */
  public void reconcile(
      long tick, boolean alive, float[] positionM, float[] velocityMps, long acknowledged) {
    if (previousTick >= 0 && tick > previousTick && acknowledged >= previousAcknowledged
        && previousAcknowledged > 0) {
      offTick += Math.abs((acknowledged - previousAcknowledged) - (tick - previousTick));
    }
    previousTick = tick;
    previousAcknowledged = acknowledged;
    if (!alive) {
      active = false;
      predictedFrom = Long.MAX_VALUE;
      return;
    }
    boolean reset = !active;
    if (active && acknowledged > measuredUpTo) {
      if (acknowledged >= predictedFrom && inputs.holds(acknowledged)) {
        inputs.predicted(acknowledged, predicted);
        double error = distanceOnGrid(predicted, positionM);
        if (error > RESET_DISTANCE_M) {
          reset = true;
        } else {
          errors.add(error);
          if (error > 0) ++corrections;
        }
      }
      measuredUpTo = acknowledged;
    }
    if (reset) {
      ++resets;
      measuredUpTo = acknowledged;
    }
    active = true;
    sphere.seed(positionM, velocityMps);
    long first = inputs.firstAfter(acknowledged);
    predictedFrom = first == 0 ? Long.MAX_VALUE : first;
    if (first == 0) return;
    for (long seq = first; seq <= inputs.newest(); ++seq) {
      step(seq);
      ++replayed;
    }
  }

  /** True while predicting (the own player is alive and was seen). */
  public boolean active() {
    return active;
  }

  /** The predicted own position (m) and velocity (m/s) after the newest input, each float[3]. */
  public void predicted(float[] positionM, float[] velocityMps) {
    sphere.position(positionM);
    sphere.velocity(velocityMps);
  }

  /** The sequence of the newest input applied (the one {@link #predicted} is after); 0: none. */
  public long newestInput() {
    return inputs.newest();
  }

  /** This stats period's errors (m). */
  public ErrorWindow errors() {
    return errors;
  }

  /** Re-seeds from the server's state instead of a measured error (spawns, teleports). */
  public long resets() {
    return resets;
  }

  /** Acknowledged inputs whose error was not 0. */
  public long corrections() {
    return corrections;
  }

  /**
   * Ticks at which the server did not apply the next input in order (PROTOCOL.md, the jitter
   * buffer: it repeated the last one while the next was late, or skipped some after a burst): the
   * difference between how far {@code last_input_sequence} and the server tick advanced between
   * snapshots. Each moves the player by up to max_speed · dt away from the prediction.
   */
  public long inputsOffTick() {
    return offTick;
  }

  /** Inputs replayed after snapshots. */
  public long replayed() {
    return replayed;
  }

  /** The input ring (for tests). */
  InputRing inputs() {
    return inputs;
  }

  private void step(long seq) {
    CharacterMotion.wish(inputs.moveRight(seq), inputs.moveForward(seq), inputs.yaw(seq), wish);
    boolean grounded = sphere.grounded();
    sphere.velocity(velocity);
    CharacterMotion.velocity(rules, wish, inputs.jump(seq), grounded, tickS, velocity);
    sphere.setVelocity(velocity);
    sphere.step(tickS);
    sphere.position(position);
    inputs.setPredicted(seq, position);
  }

  /** The distance (m) between {@code predictedM} put on the snapshot's grid and {@code serverM}. */
  private double distanceOnGrid(float[] predictedM, float[] serverM) {
    double sum = 0;
    for (int axis = 0; axis < 3; ++axis) {
      double steps = ((double) predictedM[axis] - spec.boundsMinM(axis)) / spec.positionStepM();
      double clamped = Math.max(0, Math.min(spec.positionSteps(axis) - 1, steps));
      float gridded = spec.positionM((int) Math.round(clamped), axis);
      double d = (double) gridded - serverM[axis];
      sum += d * d;
    }
    return Math.sqrt(sum);
  }
}
