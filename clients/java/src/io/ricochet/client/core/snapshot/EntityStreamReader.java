package io.ricochet.client.core.snapshot;

import java.util.Arrays;

/**
 * Reads one packed entity stream against its baseline (PROTOCOL.md, Snapshots §4 to §6), a section
 * per method in stream order, as proto/src/snapshot_decoder.cpp's StreamReader does: each returns
 * the refusal that stops it, or null. Checks come in the C++ end's order, so that a corrupt stream
 * is refused with the same reason on both ends. Owned by one {@link SnapshotDecoder}; reuses its
 * tables and scratch, so that a decode allocates nothing once they have grown.
 */
final class EntityStreamReader {
  private static final int ORDER_BITS = 5;
  private static final int ALL_ZERO_ORDER = 31; // every value coded with it is 0, no bits
  private static final int MASK_BITS = 4;
  private static final int VELOCITY_CHANGED = 8;
  private static final int POSITION_CHANGED = 4;
  private static final int ORIENTATION_CHANGED = 2;
  private static final int FLAGS_CHANGED = 1;
  private static final int INITIAL_MASK = VELOCITY_CHANGED | POSITION_CHANGED;
  private static final long MAX_PREDICTION_AGE = 255;
  private static final long MAX_ID = 0xFFFFFFFFL;
  // What readChange found, for the caller to report once it knows the reader did not fail.
  private static final int CHANGE_OK = 0;
  private static final int CHANGE_EMPTY = 1;
  private static final int CHANGE_OUT_OF_RANGE = 2;

  private final QuantizationSpec spec;
  private final int maxEntities;
  private final BitReader reader = new BitReader();
  private EntityTable kept; // the baseline without the removals, then changed
  private final EntityTable added; // new entities, ids ascending
  private byte[] removed = new byte[64]; // by baseline index
  private final int[] orders = new int[8]; // gap, velocity x y z, position x y z, orientation
  private final int[] velocity = new int[3];
  private final int[] orientation = new int[3];
  private EntityTable baseline;
  private long baselineWeight;
  private long currentWeight;

  EntityStreamReader(QuantizationSpec spec, int maxEntities, EntityTable kept, EntityTable added) {
    this.spec = spec;
    this.maxEntities = maxEntities;
    this.kept = kept;
    this.added = added;
  }

  /** Starts on {@code bytes[offset, offset + length)} against {@code baseline} of that age. */
  void start(EntityTable baseline, long baselineAge, byte[] bytes, int offset, int length) {
    this.baseline = baseline;
    reader.reset(bytes, offset, length);
    if (baselineAge == 0 || baselineAge > MAX_PREDICTION_AGE) {
      baselineWeight = 0;
      currentWeight = 0;
    } else {
      baselineWeight = (baselineAge - 1) * spec.predictionScale();
      currentWeight = (baselineAge + 1) * spec.predictionScale();
    }
    kept.count = 0;
    added.count = 0;
  }

  SnapshotRejection readRemovals() {
    long count = reader.readExpGolomb(0);
    if (reader.failed()) return readerRefusal();
    int size = baseline.count;
    if (count > size) return SnapshotRejection.REMOVED_OUT_OF_RANGE;
    if (count == 0) { // the common case: the baseline as it is
      kept.copyOf(baseline);
      return null;
    }
    if (removed.length < size) removed = new byte[Math.max(size, 2 * removed.length)];
    Arrays.fill(removed, 0, size, (byte) 0);
    int order = (int) reader.readBits(ORDER_BITS);
    long index = 0;
    for (long k = 0; k < count; ++k) {
      long gap = readCode(order);
      if (reader.failed()) return readerRefusal();
      index = k == 0 ? gap : index + 1 + gap;
      if (index >= size) return SnapshotRejection.REMOVED_OUT_OF_RANGE;
      removed[(int) index] = 1;
    }
    kept.ensureCapacity(size);
    for (int i = 0; i < size; ++i) {
      if (removed[i] == 0) kept.append(baseline, i);
    }
    return null;
  }

  SnapshotRejection readAdditions() {
    long count = reader.readExpGolomb(0);
    if (reader.failed()) return readerRefusal();
    if (kept.count + count > maxEntities) return SnapshotRejection.TOO_MANY_ENTITIES;
    if (count == 0) return null;
    if (count > reader.bitsLeft()) return SnapshotRejection.TRUNCATED;
    added.ensureCapacity((int) count);
    int order = (int) reader.readBits(ORDER_BITS);
    long id = 0;
    for (long k = 0; k < count; ++k) {
      long gap = readCode(order);
      if (reader.failed()) return readerRefusal();
      id = k == 0 ? gap : id + 1 + gap;
      if (id > MAX_ID) return SnapshotRejection.ID_OUT_OF_ORDER;
      int at = added.count++;
      added.id[at] = (int) id;
      boolean inRange = readAbsolute(at);
      if (reader.failed()) return readerRefusal();
      if (!inRange) return SnapshotRejection.VALUE_OUT_OF_RANGE;
    }
    return null;
  }

  SnapshotRejection readChanges() {
    long count = reader.readExpGolomb(0);
    if (reader.failed()) return readerRefusal();
    if (count > kept.count) return SnapshotRejection.CHANGED_OUT_OF_RANGE;
    if (count == 0) return null;
    for (int k = 0; k < orders.length; ++k) orders[k] = (int) reader.readBits(ORDER_BITS);
    long index = 0;
    int previousMask = INITIAL_MASK;
    for (long k = 0; k < count; ++k) {
      long gap = readCode(orders[0]);
      if (reader.failed()) return readerRefusal();
      index = k == 0 ? gap : index + 1 + gap;
      if (index >= kept.count) return SnapshotRejection.CHANGED_OUT_OF_RANGE;
      boolean sameMask = reader.readBool();
      int mask = sameMask ? previousMask : (int) reader.readBits(MASK_BITS);
      previousMask = mask;
      int status = readChange((int) index, mask);
      if (reader.failed()) return readerRefusal();
      if (status == CHANGE_EMPTY) return SnapshotRejection.EMPTY_CHANGE;
      if (status == CHANGE_OUT_OF_RANGE) return SnapshotRejection.VALUE_OUT_OF_RANGE;
    }
    return null;
  }

  SnapshotRejection checkEnd() {
    return reader.onlyPaddingLeft() ? null : SnapshotRejection.TRAILING_BITS;
  }

  /**
   * The kept entities and the additions merged by id into {@code view}; without additions the
   * result is {@code kept} itself, and the caller swaps tables instead ({@link #keptIsResult}).
   */
  SnapshotRejection merge(EntityTable view) {
    view.count = 0;
    view.ensureCapacity(kept.count + added.count);
    int k = 0;
    int a = 0;
    while (k < kept.count || a < added.count) {
      if (a == added.count
          || (k < kept.count && Integer.compareUnsigned(kept.id[k], added.id[a]) < 0)) {
        view.append(kept, k++);
      } else if (k == kept.count || Integer.compareUnsigned(added.id[a], kept.id[k]) < 0) {
        view.append(added, a++);
      } else {
        return SnapshotRejection.ID_OUT_OF_ORDER; // a new id already held
      }
    }
    return null;
  }

  /** Reads into {@code table} as its kept entities from now on (the decoder swapped tables). */
  void useKept(EntityTable table) {
    kept = table;
  }

  /** True when the stream added nothing: the kept entities are the snapshot. */
  boolean keptIsResult() {
    return added.count == 0;
  }

  private SnapshotRejection readerRefusal() {
    return reader.malformed() ? SnapshotRejection.BAD_CODE : SnapshotRejection.TRUNCATED;
  }

  private long readCode(int order) {
    return order == ALL_ZERO_ORDER ? 0 : reader.readExpGolomb(order);
  }

  /** A new entity's state (§5) into added[at]; false on a value out of range. */
  private boolean readAbsolute(int at) {
    boolean inRange = true;
    for (int a = 0; a < 3; ++a) {
      long steps = reader.readBits(spec.positionBits(a));
      added.position[3 * at + a] = (int) steps;
      inRange = inRange && steps < (spec.positionSteps(a) & 0xFFFFFFFFL);
    }
    int velocityLimit = spec.velocityLimit();
    boolean moving = reader.readBool();
    for (int a = 0; a < 3; ++a) {
      int value = 0;
      if (moving) {
        long raw = reader.readBits(spec.velocityBits());
        inRange = inRange && raw <= 2L * velocityLimit;
        value = (int) (raw - velocityLimit);
      }
      added.velocity[3 * at + a] = value;
    }
    int orientationLimit = spec.orientationLimit();
    int largest = 3;
    boolean rotated = reader.readBool();
    if (rotated) largest = (int) reader.readBits(2);
    added.largest[at] = (byte) largest;
    for (int k = 0; k < 3; ++k) {
      int value = 0;
      if (rotated) {
        long raw = reader.readBits(spec.orientationBits());
        inRange = inRange && raw <= 2L * orientationLimit;
        value = (int) (raw - orientationLimit);
      }
      added.orientation[3 * at + k] = value;
    }
    added.flags[at] = reader.readBool() ? (byte) reader.readBits(8) : 0;
    return inRange;
  }

  /**
   * Applies the delta after the mask (§6) to kept[index], which holds its baseline state; the
   * reader may fail. As proto snapshot_layout::read_delta: a velocity out of range stops before
   * the position; any other value out of range is reported after the entity's last field.
   */
  private int readChange(int index, int mask) {
    int base = 3 * index;
    int velocityLimit = spec.velocityLimit();
    boolean inRange = true;
    for (int a = 0; a < 3; ++a) velocity[a] = kept.velocity[base + a];
    if ((mask & VELOCITY_CHANGED) != 0) {
      for (int a = 0; a < 3; ++a) {
        long value = velocity[a] + BitReader.unzigzag(readCode(orders[1 + a]));
        inRange = inRange && value >= -velocityLimit && value <= velocityLimit;
        velocity[a] = inRange ? (int) value : 0;
      }
    }
    if (!inRange) return CHANGE_OUT_OF_RANGE;
    // The position follows from the velocities, then its residual if the mask says so.
    boolean changed = false;
    boolean hasResidual = (mask & POSITION_CHANGED) != 0;
    for (int a = 0; a < 3; ++a) {
      long weighted = kept.velocity[base + a] * baselineWeight + velocity[a] * currentWeight;
      long motion = (weighted + (1L << 16)) >> 17;
      long residual = hasResidual ? BitReader.unzigzag(readCode(orders[4 + a])) : 0;
      long was = kept.position[base + a] & 0xFFFFFFFFL;
      long value = was + motion + residual;
      inRange = inRange && value >= 0 && value < (spec.positionSteps(a) & 0xFFFFFFFFL);
      changed = changed || value != was || velocity[a] != kept.velocity[base + a];
      kept.position[base + a] = (int) value;
      kept.velocity[base + a] = velocity[a];
    }
    if ((mask & ORIENTATION_CHANGED) != 0) {
      int orientationLimit = spec.orientationLimit();
      for (int k = 0; k < 3; ++k) orientation[k] = kept.orientation[base + k];
      int largest = kept.largest[index];
      if (reader.readBool()) {
        for (int k = 0; k < 3; ++k) {
          long value = orientation[k] + BitReader.unzigzag(readCode(orders[7]));
          inRange = inRange && value >= -orientationLimit && value <= orientationLimit;
          orientation[k] = (int) value;
        }
      } else {
        largest = (int) reader.readBits(2);
        for (int k = 0; k < 3; ++k) {
          long raw = reader.readBits(spec.orientationBits());
          inRange = inRange && raw <= 2L * orientationLimit;
          orientation[k] = (int) (raw - orientationLimit);
        }
      }
      changed = changed || largest != kept.largest[index];
      kept.largest[index] = (byte) largest;
      for (int k = 0; k < 3; ++k) {
        changed = changed || orientation[k] != kept.orientation[base + k];
        kept.orientation[base + k] = orientation[k];
      }
    }
    if ((mask & FLAGS_CHANGED) != 0) {
      byte flags = (byte) reader.readBits(8);
      changed = changed || flags != kept.flags[index];
      kept.flags[index] = flags;
    }
    if (!inRange) return CHANGE_OUT_OF_RANGE;
    return changed ? CHANGE_OK : CHANGE_EMPTY;
  }
}
