package io.ricochet.client.core.snapshot;

/**
 * The entities a client holds after its newest decoded snapshot, read in place: the quantised
 * integers the server sent (bit for bit the server's quantised state) and their values in metres,
 * m/s and unit quaternions, by index 0..{@link #count()}-1 in ascending id order. One view per
 * {@link SnapshotDecoder}, filled by its {@link SnapshotDecoder#decode} and valid until the next
 * accepted decode (a refused one leaves it as it was); read it on the thread that decodes, or copy
 * what you need. No accessor allocates.
 */
public final class SnapshotView {
  private final QuantizationSpec spec;
  private EntityTable table;
  private long tick;
  private boolean ready;

  SnapshotView(QuantizationSpec spec, EntityTable empty) {
    this.spec = spec;
    this.table = empty;
  }

  void show(long tick, EntityTable table) {
    this.tick = tick;
    this.table = table;
    this.ready = true;
  }

  /** False until a snapshot was decoded (then count() is 0). */
  public boolean hasSnapshot() {
    return ready;
  }

  /** The server tick shown (unsigned 32-bit value). */
  public long tick() {
    return tick;
  }

  /** Entities held. */
  public int count() {
    return table.count;
  }

  /** The spec the values are dequantised with. */
  public QuantizationSpec spec() {
    return spec;
  }

  /** Entity {@code index}'s id (unsigned 32-bit value). */
  public long id(int index) {
    return table.id[checked(index)] & 0xFFFFFFFFL;
  }

  /** The index of entity {@code id}, or -1 when not held (binary search, O(log n)). */
  public int indexOf(long id) {
    int low = 0;
    int high = table.count - 1;
    while (low <= high) {
      int middle = (low + high) >>> 1;
      long at = table.id[middle] & 0xFFFFFFFFL;
      if (at < id)
        low = middle + 1;
      else if (at > id)
        high = middle - 1;
      else
        return middle;
    }
    return -1;
  }

  /** Position along {@code axis} (0 x, 1 y, 2 z) in steps from the bounds' minimum (unsigned). */
  public int positionSteps(int index, int axis) {
    return table.position[3 * checked(index) + checkedAxis(axis)];
  }

  /** Velocity along {@code axis} in steps of the spec's velocity step. */
  public int velocitySteps(int index, int axis) {
    return table.velocity[3 * checked(index) + checkedAxis(axis)];
  }

  /** The orientation component left out (0 x, 1 y, 2 z, 3 w). */
  public int orientationLargest(int index) {
    return table.largest[checked(index)];
  }

  /** Smallest-three component {@code k} (0..2, the other three in x y z w order), in steps. */
  public int orientationSteps(int index, int k) {
    return table.orientation[3 * checked(index) + checkedAxis(k)];
  }

  /** The game's 8 flag bits ({@link EntityFlags}). */
  public int flags(int index) {
    return table.flags[checked(index)] & 0xFF;
  }

  /** Position along {@code axis}, m (the centre of its 1 mm step), as proto::dequantize. */
  public float positionM(int index, int axis) {
    return spec.positionM(positionSteps(index, axis), axis);
  }

  /** Velocity along {@code axis}, m/s. */
  public float velocityMps(int index, int axis) {
    return spec.velocityMps(velocitySteps(index, axis));
  }

  /** The unit orientation quaternion into {@code xyzw} (4 floats: x, y, z, w). */
  public void orientation(int index, float[] xyzw) {
    int base = 3 * checked(index);
    spec.orientation(table.largest[index], table.orientation[base], table.orientation[base + 1],
        table.orientation[base + 2], xyzw);
  }

  private int checked(int index) {
    if (index < 0 || index >= table.count) {
      throw new IndexOutOfBoundsException("entity " + index + " of " + table.count);
    }
    return index;
  }

  private static int checkedAxis(int axis) {
    if (axis < 0 || axis > 2) throw new IndexOutOfBoundsException("axis " + axis);
    return axis;
  }
}
