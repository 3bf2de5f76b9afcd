package io.ricochet.client.core.predict;

import io.ricochet.client.core.snapshot.SnapshotView;
import java.util.Arrays;

/**
 * Where the other entities are shown: interpolated {@link #DELAY_MS} behind the newest snapshot,
 * between the two snapshots around that render time, and never extrapolated (past the newest
 * snapshot, or when one of the two lacks the entity, the nearest snapshot's state is held). The
 * render time also gives each Input's {@code view_tick} and {@code view_fraction} (PROTOCOL.md
 * Input: what the client was showing, for lag compensation).
 *
 * <p>The server's clock is estimated from snapshot arrivals ({@code nowUs} of the caller's
 * monotonic clock): the newest snapshot's tick at its arrival, advanced at the tick rate. Holds the
 * last {@link #HISTORY} snapshots' positions; arrays grow to the largest snapshot, then nothing is
 * allocated. Not thread-safe.
 */
public final class Interpolator {
  /** How far behind the newest snapshot the others are shown, ms. */
  public static final int DELAY_MS = 100;
  /** Snapshots kept. */
  public static final int HISTORY = 32;

  private final double tickRateHz;
  private final long[] ticks = new long[HISTORY];
  private final int[] counts = new int[HISTORY];
  private final long[][] ids = new long[HISTORY][];
  private final float[][] positions = new float[HISTORY][];
  private int held;
  private int newestSlot = -1;
  private long newestArrivalUs;

  /** An interpolator for a match of {@code tickRateHz}. */
  public Interpolator(int tickRateHz) {
    this.tickRateHz = tickRateHz;
    for (int k = 0; k < HISTORY; ++k) {
      ids[k] = new long[16];
      positions[k] = new float[48];
    }
  }

  /** Keeps the positions of a decoded snapshot that arrived at {@code nowUs}. */
  public void add(SnapshotView view, long nowUs) {
    int slot = nextSlot(view.tick(), view.count());
    if (slot < 0) return;
    for (int i = 0; i < view.count(); ++i) {
      ids[slot][i] = view.id(i);
      for (int axis = 0; axis < 3; ++axis) positions[slot][3 * i + axis] = view.positionM(i, axis);
    }
    keep(slot, view.tick(), view.count(), nowUs);
  }

  /**
   * Keeps {@code count} entities of tick {@code tick} from another source than the decoder (a
   * replay, a test): {@code ids[i]} at {@code positionsM[3i, 3i + 3)}, arrived at {@code nowUs}.
   */
  public void add(long tick, int count, long[] entityIds, float[] positionsM, long nowUs) {
    int slot = nextSlot(tick, count);
    if (slot < 0) return;
    System.arraycopy(entityIds, 0, ids[slot], 0, count);
    System.arraycopy(positionsM, 0, positions[slot], 0, 3 * count);
    keep(slot, tick, count, nowUs);
  }

  /** The slot for a snapshot of {@code tick} with {@code n} entities; -1: late or repeated. */
  private int nextSlot(long tick, int n) {
    if (newestSlot >= 0 && tick <= ticks[newestSlot]) return -1;
    int slot = (newestSlot + 1) % HISTORY;
    if (ids[slot].length < n) {
      ids[slot] = new long[n];
      positions[slot] = new float[3 * n];
    }
    return slot;
  }

  private void keep(int slot, long tick, int n, long nowUs) {
    ticks[slot] = tick;
    counts[slot] = n;
    newestSlot = slot;
    newestArrivalUs = nowUs;
    if (held < HISTORY) ++held;
  }

  /** Whether a snapshot was added. */
  public boolean hasSnapshot() {
    return held > 0;
  }

  /**
   * The server tick shown at {@code nowUs}, in ticks with a fraction: the estimated server tick
   * less the delay, within the held snapshots (never past the newest).
   */
  public double renderTick(long nowUs) {
    if (held == 0) return 0;
    double estimated = ticks[newestSlot] + (nowUs - newestArrivalUs) * tickRateHz / 1e6;
    double render = estimated - DELAY_MS * tickRateHz / 1000.0;
    double oldest = ticks[slotAge(held - 1)];
    return Math.max(oldest, Math.min(ticks[newestSlot], render));
  }

  /** {@code view_tick} for an input sampled at {@code nowUs}: 0 before any snapshot. */
  public long viewTick(long nowUs) {
    return held == 0 ? 0 : (long) Math.floor(renderTick(nowUs));
  }

  /** {@code view_fraction} (1/256 of a tick past {@link #viewTick}) at {@code nowUs}. */
  public int viewFraction(long nowUs) {
    if (held == 0) return 0;
    double render = renderTick(nowUs);
    return Math.min(255, (int) Math.floor((render - Math.floor(render)) * 256));
  }

  /**
   * Writes entity {@code id}'s position (m) at render tick {@code renderTick} into {@code out}
   * (float[3]); false when no held snapshot has it.
   */
  public boolean position(long id, double renderTick, float[] out) {
    if (held == 0) return false;
    int after = -1;
    int before = -1;
    for (int age = 0; age < held; ++age) {
      int slot = slotAge(age);
      if (ticks[slot] >= renderTick) {
        after = slot;
      } else {
        before = slot;
        break;
      }
    }
    int a = before >= 0 ? indexOf(before, id) : -1;
    int b = after >= 0 ? indexOf(after, id) : -1;
    if (a >= 0 && b >= 0) {
      double t = (renderTick - ticks[before]) / (double) (ticks[after] - ticks[before]);
      for (int axis = 0; axis < 3; ++axis) {
        float pa = positions[before][3 * a + axis];
        float pb = positions[after][3 * b + axis];
        out[axis] = (float) (pa + (pb - pa) * t);
      }
      return true;
    }
    int slot = b >= 0 ? after : before;
    int index = b >= 0 ? b : a;
    if (index < 0) return false;
    System.arraycopy(positions[slot], 3 * index, out, 0, 3);
    return true;
  }

  /** Forgets every snapshot (a new game connection). */
  public void clear() {
    held = 0;
    newestSlot = -1;
    Arrays.fill(counts, 0);
  }

  private int slotAge(int age) {
    return ((newestSlot - age) % HISTORY + HISTORY) % HISTORY;
  }

  private int indexOf(int slot, long id) {
    long[] slotIds = ids[slot];
    for (int i = 0; i < counts[slot]; ++i) {
      if (slotIds[i] == id) return i;
    }
    return -1;
  }
}
