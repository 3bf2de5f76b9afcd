package io.ricochet.client;

import io.ricochet.client.core.game.PlayerStatus;
import io.ricochet.client.core.game.ServerPayloadReader;
import io.ricochet.client.core.predict.Interpolator;
import io.ricochet.client.core.predict.Predictor;
import io.ricochet.client.core.snapshot.QuantizationSpec;
import io.ricochet.client.core.snapshot.SnapshotView;
import java.util.Arrays;

/**
 * One decoded ServerPayload as {@link GameListener#onSnapshot} sees it: the entities of the
 * snapshot (ids ascending, quantised integers and their values in metres, m/s and unit
 * quaternions) and the rest of the payload (the server tick, the entity this client controls, the
 * last input the server applied, the own player's status). <b>Valid only during the callback</b>:
 * the object is pooled and refilled for a later snapshot once the callback returns; copy what you
 * keep. No accessor allocates.
 */
public final class GameSnapshot {
  private final QuantizationSpec spec;
  private int count;
  private long[] ids = new long[16];
  private int[] position = new int[48];
  private int[] velocity = new int[48];
  private int[] largest = new int[16];
  private int[] orientation = new int[48];
  private int[] flags = new int[16];
  private long tick;
  private long yourEntityId;
  private long lastInputSequence;
  private final PlayerStatus status = new PlayerStatus();
  private float[] shown = new float[48];
  private double renderTick;
  private boolean predicting;
  private long predictedInput;
  private final float[] predictedPosition = new float[3];
  private final float[] predictedVelocity = new float[3];
  private final float[] sample = new float[3];

  GameSnapshot(QuantizationSpec spec) {
    this.spec = spec;
  }

  /** Copies the decoder's view and the payload's fields (the I/O thread, before the hand-off). */
  void fill(SnapshotView view, ServerPayloadReader payload) {
    count = view.count();
    if (ids.length < count) grow(count);
    for (int i = 0; i < count; ++i) {
      ids[i] = view.id(i);
      for (int a = 0; a < 3; ++a) {
        position[3 * i + a] = view.positionSteps(i, a);
        velocity[3 * i + a] = view.velocitySteps(i, a);
        orientation[3 * i + a] = view.orientationSteps(i, a);
      }
      largest[i] = view.orientationLargest(i);
      flags[i] = view.flags(i);
    }
    tick = view.tick();
    yourEntityId = payload.yourEntityId();
    lastInputSequence = payload.lastInputSequence();
    status.copyFrom(payload.status());
  }

  /**
   * Adds what the client shows (the I/O thread, after {@link #fill}): every entity interpolated at
   * the render tick of {@code nowUs} (100 ms behind, never extrapolated), and the own player as
   * predicted after the newest input ({@code predictor} null or idle: as the snapshot says).
   */
  void fillShown(Predictor predictor, Interpolator interpolator, long nowUs) {
    if (shown.length < 3 * count) shown = new float[3 * Math.max(count, ids.length)];
    renderTick = interpolator.hasSnapshot() ? interpolator.renderTick(nowUs) : tick;
    predicting = predictor != null && predictor.active();
    if (predicting) predictor.predicted(predictedPosition, predictedVelocity);
    predictedInput = predicting ? predictor.newestInput() : 0;
    for (int i = 0; i < count; ++i) {
      boolean own = ids[i] == yourEntityId;
      if (own && predicting) {
        System.arraycopy(predictedPosition, 0, shown, 3 * i, 3);
      } else if (!own && interpolator.position(ids[i], renderTick, sample)) {
        System.arraycopy(sample, 0, shown, 3 * i, 3);
      } else {
        for (int a = 0; a < 3; ++a) shown[3 * i + a] = positionM(i, a);
      }
    }
  }

  /** Whether the own player is predicted (alive, and the join reply's world was usable). */
  public boolean predicting() {
    return predicting;
  }

  /**
   * The sequence of the newest own input the prediction includes (the server acknowledges it in a
   * later snapshot's {@link #lastInputSequence}); 0 when not predicting.
   */
  public long predictedInput() {
    return predictedInput;
  }

  /** The own player's predicted position after the newest input, m; {@code axis} 0..2. */
  public float predictedPositionM(int axis) {
    return predictedPosition[checkedAxis(axis)];
  }

  /** The own player's predicted velocity after the newest input, m/s; {@code axis} 0..2. */
  public float predictedVelocityMps(int axis) {
    return predictedVelocity[checkedAxis(axis)];
  }

  /**
   * Where to draw entity {@code index}, m: the others interpolated at {@link #renderTick}, the own
   * player as predicted (as the snapshot says when not predicting).
   */
  public float shownPositionM(int index, int axis) {
    return shown[3 * checked(index) + checkedAxis(axis)];
  }

  /** The server tick (with a fraction) the others are shown at: 100 ms behind the newest. */
  public double renderTick() {
    return renderTick;
  }

  private void grow(int atLeast) {
    int size = Math.max(atLeast, ids.length * 2);
    ids = Arrays.copyOf(ids, size);
    position = Arrays.copyOf(position, 3 * size);
    velocity = Arrays.copyOf(velocity, 3 * size);
    largest = Arrays.copyOf(largest, size);
    orientation = Arrays.copyOf(orientation, 3 * size);
    flags = Arrays.copyOf(flags, size);
  }

  /** The server tick of the state shown (unsigned 32-bit). */
  public long tick() {
    return tick;
  }

  /** The entity this client controls (0 when the server named none). */
  public long yourEntityId() {
    return yourEntityId;
  }

  /** The last input sequence the server applied for this client (0: none yet). */
  public long lastInputSequence() {
    return lastInputSequence;
  }

  /** Entities held. */
  public int count() {
    return count;
  }

  /** The index of entity {@code id}, or -1 (binary search). */
  public int indexOf(long id) {
    int low = 0;
    int high = count - 1;
    while (low <= high) {
      int middle = (low + high) >>> 1;
      if (ids[middle] < id) {
        low = middle + 1;
      } else if (ids[middle] > id) {
        high = middle - 1;
      } else {
        return middle;
      }
    }
    return -1;
  }

  /** Entity {@code index}'s id. */
  public long id(int index) {
    return ids[checked(index)];
  }

  /** Position along {@code axis} (0 x, 1 y, 2 z, +Y up), m: the centre of its quantisation step. */
  public float positionM(int index, int axis) {
    return spec.positionM(positionSteps(index, axis), axis);
  }

  /** Position along {@code axis} in steps from the bounds' minimum, as the server sent it. */
  public int positionSteps(int index, int axis) {
    return position[3 * checked(index) + checkedAxis(axis)];
  }

  /** Velocity along {@code axis}, m/s. */
  public float velocityMps(int index, int axis) {
    return spec.velocityMps(velocity[3 * checked(index) + checkedAxis(axis)]);
  }

  /** The unit orientation quaternion into {@code xyzw} (x, y, z, w). */
  public void orientation(int index, float[] xyzw) {
    int base = 3 * checked(index);
    spec.orientation(
        largest[index], orientation[base], orientation[base + 1], orientation[base + 2], xyzw);
  }

  /** The entity's flag bits ({@link io.ricochet.client.core.snapshot.EntityFlags}). */
  public int flags(int index) {
    return flags[checked(index)];
  }

  /** The own player's status (health, armour, weapon, ammunition, alive, team ...). */
  public PlayerStatus status() {
    return status;
  }

  private int checked(int index) {
    if (index < 0 || index >= count) {
      throw new IndexOutOfBoundsException("entity " + index + " of " + count);
    }
    return index;
  }

  private static int checkedAxis(int axis) {
    if (axis < 0 || axis > 2) throw new IndexOutOfBoundsException("axis " + axis);
    return axis;
  }
}
