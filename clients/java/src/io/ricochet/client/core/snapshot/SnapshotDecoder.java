package io.ricochet.client.core.snapshot;

import com.google.protobuf.ByteString;
import io.ricochet.wire.SnapshotProto.Snapshot;

/**
 * Decodes a client's snapshots (PROTOCOL.md, Snapshots; proto::SnapshotDecoder, bit for bit):
 * validates each against the baseline it names among the last {@code ringSize} decoded ones,
 * rebuilds the entity set the client holds and keeps it as a baseline for later snapshots. Sans-IO
 * and single-threaded: the game layer calls {@link #decode} with each {@code
 * ServerPayload.snapshot} and echoes {@link #newestTick()} as {@code ack_snapshot_tick}.
 *
 * <p>Untrusted input: every count, index, code and value is checked; a refusal returns false,
 * counts its {@link SnapshotRejection} and changes nothing (the view and the baselines stay as they
 * were). No exception leaves decode for bad bytes. Once its tables have grown to the largest entity
 * set seen, a decode allocates nothing.
 */
public final class SnapshotDecoder {
  /** Largest entity stream accepted, bytes (a game packet is at most 1200 bytes). */
  public static final int MAX_STREAM_BYTES = 1200;
  /** Snapshots kept as baselines by default: as many as the server remembers. */
  public static final int DEFAULT_RING_SIZE = 64;
  /** Largest entity set accepted by default. */
  public static final int DEFAULT_MAX_ENTITIES = 65536;

  private static final long MAX_TICK = 0xFFFFFFFFL;

  private final EntityTable[] ring;
  private final long[] ringTicks;
  private final boolean[] ringValid;
  private final EntityTable empty = new EntityTable(1);
  private final EntityStreamReader stream;
  private final SnapshotView view;
  private final byte[] streamBuffer = new byte[MAX_STREAM_BYTES];
  private EntityTable next = new EntityTable(16); // the snapshot being decoded
  private EntityTable kept = new EntityTable(16);
  private boolean hasNewest;
  private long newestTick;
  private long accepted;
  private final long[] rejections = new long[SnapshotRejection.values().length];
  private SnapshotRejection lastRejection;

  /** A decoder with the default ring (64) and entity limit (65536). */
  public SnapshotDecoder(QuantizationSpec spec) {
    this(spec, DEFAULT_RING_SIZE, DEFAULT_MAX_ENTITIES);
  }

  /**
   * {@code spec}: the match's (the same as the server's encoder). {@code ringSize}: decoded
   * snapshots kept as baselines, 2..1024, at least the server's (64). {@code maxEntities}: larger
   * entity sets are refused, > 0.
   */
  public SnapshotDecoder(QuantizationSpec spec, int ringSize, int maxEntities) {
    if (spec == null) throw new NullPointerException("spec");
    if (ringSize < 2 || ringSize > 1024) {
      throw new IllegalArgumentException("ringSize must be 2..1024, got " + ringSize);
    }
    if (maxEntities <= 0) {
      throw new IllegalArgumentException("maxEntities must be > 0, got " + maxEntities);
    }
    ring = new EntityTable[ringSize];
    for (int i = 0; i < ringSize; ++i) ring[i] = new EntityTable(16);
    ringTicks = new long[ringSize];
    ringValid = new boolean[ringSize];
    stream = new EntityStreamReader(spec, maxEntities, kept, new EntityTable(16));
    view = new SnapshotView(spec, empty);
  }

  /**
   * Decodes a received snapshot message; copies its entity stream into a buffer of the decoder's,
   * so allocates nothing. True when accepted ({@link #view()} shows it), false when refused
   * ({@link #lastRejection()} says why).
   */
  public boolean decode(Snapshot in) {
    ByteString entities = in.getEntities();
    int length = entities.size();
    if (length > MAX_STREAM_BYTES) return refuse(SnapshotRejection.OVERSIZED);
    entities.copyTo(streamBuffer, 0);
    return decode(in.getTick() & MAX_TICK, in.getBaselineAge() & MAX_TICK, streamBuffer, 0, length);
  }

  /**
   * Decodes a snapshot from its fields: {@code tick} and {@code baselineAge} as unsigned 32-bit
   * values (0..2^32-1), the packed entity stream in {@code bytes[offset, offset + length)} (read,
   * not kept). True when accepted, false when refused.
   */
  public boolean decode(long tick, long baselineAge, byte[] bytes, int offset, int length) {
    if (tick < 0 || tick > MAX_TICK || baselineAge < 0 || baselineAge > MAX_TICK) {
      throw new IllegalArgumentException("tick and baselineAge are unsigned 32-bit values");
    }
    if (offset < 0 || length < 0 || offset > bytes.length - length) {
      throw new IndexOutOfBoundsException(
          "decode(" + offset + ", " + length + ") of " + bytes.length);
    }
    // The header: size, tick order, baseline.
    if (length > MAX_STREAM_BYTES) return refuse(SnapshotRejection.OVERSIZED);
    if (hasNewest && tick <= newestTick) return refuse(SnapshotRejection.STALE);
    if (baselineAge > tick) return refuse(SnapshotRejection.BASELINE_AFTER_TICK);
    EntityTable baseline = empty;
    if (baselineAge != 0) {
      long baselineTick = tick - baselineAge;
      int slot = (int) (baselineTick % ring.length);
      if (!ringValid[slot] || ringTicks[slot] != baselineTick) {
        return refuse(SnapshotRejection.UNKNOWN_BASELINE);
      }
      baseline = ring[slot];
    }

    // The stream, section by section, into a new table.
    stream.start(baseline, baselineAge, bytes, offset, length);
    SnapshotRejection refusal = stream.readRemovals();
    if (refusal == null) refusal = stream.readAdditions();
    if (refusal == null) refusal = stream.readChanges();
    if (refusal == null) refusal = stream.checkEnd();
    if (refusal == null && !stream.keptIsResult()) refusal = stream.merge(next);
    if (refusal != null) return refuse(refusal);

    // The baseline is read; its slot may now take the new table.
    EntityTable result = next;
    if (stream.keptIsResult()) {
      result = kept;
      kept = next;
      stream.useKept(kept);
    }
    int slot = (int) (tick % ring.length);
    next = ring[slot];
    ring[slot] = result;
    ringTicks[slot] = tick;
    ringValid[slot] = true;
    hasNewest = true;
    newestTick = tick;
    ++accepted;
    view.show(tick, result);
    return true;
  }

  /**
   * The entities held after the newest accepted snapshot; the same object for the decoder's life.
   */
  public SnapshotView view() {
    return view;
  }

  /** True once a snapshot was accepted. */
  public boolean hasSnapshot() {
    return hasNewest;
  }

  /** The tick to echo as ack_snapshot_tick (unsigned; meaningful once hasSnapshot()). */
  public long newestTick() {
    return newestTick;
  }

  /** Snapshots accepted since construction. */
  public long accepted() {
    return accepted;
  }

  /** Snapshots refused for {@code reason} since construction. */
  public long rejections(SnapshotRejection reason) {
    return rejections[reason.ordinal()];
  }

  /** Why the last refused snapshot was refused; null before any refusal. */
  public SnapshotRejection lastRejection() {
    return lastRejection;
  }

  private boolean refuse(SnapshotRejection reason) {
    ++rejections[reason.ordinal()];
    lastRejection = reason;
    return false;
  }
}
