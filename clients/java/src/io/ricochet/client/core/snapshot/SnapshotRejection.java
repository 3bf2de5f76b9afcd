package io.ricochet.client.core.snapshot;

/**
 * Why a {@link SnapshotDecoder} refused a snapshot (PROTOCOL.md, Snapshots §9). Every refusal
 * leaves the decoder as it was and is counted by reason ({@link SnapshotDecoder#rejections}).
 */
public enum SnapshotRejection {
  /** The entity stream is longer than {@link SnapshotDecoder#MAX_STREAM_BYTES}. */
  OVERSIZED("oversized"),
  /** The tick is not newer than the newest decoded one (a late or duplicated datagram). */
  STALE("stale"),
  /** {@code baseline_age} is greater than the tick. */
  BASELINE_AFTER_TICK("baseline_after_tick"),
  /** The baseline tick is not (or no longer) among the snapshots the decoder keeps. */
  UNKNOWN_BASELINE("unknown_baseline"),
  /** The stream ended inside a field. */
  TRUNCATED("truncated"),
  /** An Exp-Golomb code body wider than 42 bits. */
  BAD_CODE("bad_code"),
  /** More removals than baseline entities, or a removal index past them. */
  REMOVED_OUT_OF_RANGE("removed_out_of_range"),
  /** A new entity's id is 2^32 or more, or already held. */
  ID_OUT_OF_ORDER("id_out_of_order"),
  /** More entities than the decoder's limit. */
  TOO_MANY_ENTITIES("too_many_entities"),
  /** More changes than kept entities, or a change index past them. */
  CHANGED_OUT_OF_RANGE("changed_out_of_range"),
  /** A change that leaves the entity as its baseline. */
  EMPTY_CHANGE("empty_change"),
  /** A position, velocity or orientation component outside the spec's ranges. */
  VALUE_OUT_OF_RANGE("value_out_of_range"),
  /** Anything but fewer than 8 zero bits after the last field. */
  TRAILING_BITS("trailing_bits");

  private final String counterName;

  SnapshotRejection(String counterName) {
    this.counterName = counterName;
  }

  /** The reason's name in counters and logs, the same as the C++ end's (snapshot_codec.h). */
  public String counterName() {
    return counterName;
  }
}
