package io.ricochet.client.core.predict;

/**
 * The own inputs a prediction may have to replay, newest {@link #CAPACITY}, each with the position
 * predicted after it: a ring of primitive arrays, nothing allocated after construction. Sequences
 * are the wire's (1, 2, 3 ... per game connection). Not thread-safe.
 */
public final class InputRing {
  /** Inputs held: more than 4 s at 60 Hz, the most a reconciliation replays. */
  public static final int CAPACITY = 256;

  private final long[] sequence = new long[CAPACITY];
  private final int[] moveRight = new int[CAPACITY];
  private final int[] moveForward = new int[CAPACITY];
  private final float[] yaw = new float[CAPACITY];
  private final boolean[] jump = new boolean[CAPACITY];
  private final float[] predicted = new float[3 * CAPACITY];
  private long newest; // 0: none

  /** Keeps input {@code seq} (one more than the last pushed, or after a clear any). */
  public void push(long seq, int moveRight, int moveForward, float yawRad, boolean jump) {
    int slot = (int) (seq % CAPACITY);
    sequence[slot] = seq;
    this.moveRight[slot] = moveRight;
    this.moveForward[slot] = moveForward;
    yaw[slot] = yawRad;
    this.jump[slot] = jump;
    newest = seq;
  }

  /** Forgets everything (a new game connection restarts its sequences). */
  public void clear() {
    java.util.Arrays.fill(sequence, 0);
    newest = 0;
  }

  /** The newest sequence pushed, 0 when none. */
  public long newest() {
    return newest;
  }

  /** Whether input {@code seq} is still held. */
  public boolean holds(long seq) {
    return seq > 0 && sequence[(int) (seq % CAPACITY)] == seq;
  }

  /** The oldest sequence after {@code acknowledged} that is held, or 0 when there is none. */
  public long firstAfter(long acknowledged) {
    long first = Math.max(acknowledged + 1, newest - CAPACITY + 1);
    return first <= newest && holds(first) ? first : 0;
  }

  int moveRight(long seq) {
    return moveRight[(int) (seq % CAPACITY)];
  }

  int moveForward(long seq) {
    return moveForward[(int) (seq % CAPACITY)];
  }

  float yaw(long seq) {
    return yaw[(int) (seq % CAPACITY)];
  }

  boolean jump(long seq) {
    return jump[(int) (seq % CAPACITY)];
  }

  /** Records where input {@code seq} (held) left the sphere, m. */
  void setPredicted(long seq, float[] positionM) {
    System.arraycopy(positionM, 0, predicted, 3 * (int) (seq % CAPACITY), 3);
  }

  /** Where input {@code seq} (held) left the sphere, m, into {@code out}. */
  void predicted(long seq, float[] out) {
    System.arraycopy(predicted, 3 * (int) (seq % CAPACITY), out, 0, 3);
  }
}
