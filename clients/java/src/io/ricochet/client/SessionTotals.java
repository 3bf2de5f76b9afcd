package io.ricochet.client;

import io.ricochet.client.core.game.GameSession;
import io.ricochet.client.core.game.PayloadRefusal;
import io.ricochet.client.core.snapshot.SnapshotRejection;
import io.ricochet.client.core.transport.DropReason;
import io.ricochet.client.core.transport.TransportCounters;

/**
 * A game connection's counts over all its sessions (a reconnect starts a new one from zero): the
 * ended sessions' folded in, the current one's added on demand. The I/O thread's own.
 */
final class SessionTotals {
  private long bytesIn;
  private long bytesOut;
  private long snapshots;
  private long missed;
  private final long[] refusals = new long[PayloadRefusal.values().length];
  private final long[] rejections = new long[SnapshotRejection.values().length];
  private final long[] drops = new long[DropReason.values().length];

  /** Adds an ended session's counts. */
  void fold(GameSession session) {
    TransportCounters counters = session.transportCounters();
    bytesIn += counters.bytesIn();
    bytesOut += counters.bytesOut();
    snapshots += session.snapshotsReceived();
    missed += session.snapshotsMissed();
    for (PayloadRefusal reason : PayloadRefusal.values()) {
      refusals[reason.ordinal()] += session.refusals(reason);
    }
    for (SnapshotRejection reason : SnapshotRejection.values()) {
      rejections[reason.ordinal()] += session.decoder().rejections(reason);
    }
    for (DropReason reason : DropReason.values()) {
      drops[reason.ordinal()] += counters.dropped(reason);
    }
  }

  /** Datagram bytes received, with {@code current}'s. */
  long bytesIn(GameSession current) {
    return bytesIn + current.transportCounters().bytesIn();
  }

  /** Datagram bytes sent, with {@code current}'s. */
  long bytesOut(GameSession current) {
    return bytesOut + current.transportCounters().bytesOut();
  }

  /** Snapshots accepted, with {@code current}'s. */
  long snapshots(GameSession current) {
    return snapshots + current.snapshotsReceived();
  }

  /** Snapshots lost, with {@code current}'s. */
  long missed(GameSession current) {
    return missed + current.snapshotsMissed();
  }

  /** Refusals by {@link PayloadRefusal} ordinal, with {@code current}'s (a new array). */
  long[] refusals(GameSession current) {
    long[] out = refusals.clone();
    for (PayloadRefusal reason : PayloadRefusal.values()) {
      out[reason.ordinal()] += current.refusals(reason);
    }
    return out;
  }

  /** Snapshot rejections by {@link SnapshotRejection} ordinal, with {@code current}'s. */
  long[] rejections(GameSession current) {
    long[] out = rejections.clone();
    for (SnapshotRejection reason : SnapshotRejection.values()) {
      out[reason.ordinal()] += current.decoder().rejections(reason);
    }
    return out;
  }

  /** Datagram drops by {@link DropReason} ordinal, with {@code current}'s. */
  long[] drops(GameSession current) {
    long[] out = drops.clone();
    for (DropReason reason : DropReason.values()) {
      out[reason.ordinal()] += current.transportCounters().dropped(reason);
    }
    return out;
  }
}
