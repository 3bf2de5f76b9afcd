package io.ricochet.client;

import io.ricochet.client.core.game.PayloadRefusal;
import io.ricochet.client.core.snapshot.SnapshotRejection;
import io.ricochet.client.core.transport.DropReason;

/**
 * A game connection's figures over the last period (about a second), given to {@link
 * GameListener#onStats}: round trip, snapshots received and lost per second, bytes per second
 * each way, and since the start the time to the first snapshot and every refusal by reason.
 * Immutable.
 */
public final class GameStats {
  private final double periodS;
  private final double rttMs;
  private final double snapshotsPerSecond;
  private final double snapshotsLostPerSecond;
  private final double bytesInPerSecond;
  private final double bytesOutPerSecond;
  private final double firstSnapshotAfterMs;
  private final long snapshotsReceived;
  private final long snapshotsLost;
  private final long snapshotsSkipped;
  private final long[] payloadRefusals;
  private final long[] snapshotRejections;
  private final long[] datagramDrops;
  private final Prediction prediction;

  /**
   * The prediction's figures of a period (PROTOCOL.md Prediction and reconciliation): the error is
   * the distance between where the client predicted an acknowledged input to leave its player and
   * where the server's snapshot says it is, m, as nearest-rank percentiles (stats/percentile.h).
   */
  static final class Prediction {
    final boolean predicting;
    final int samples;
    final double p50M;
    final double p99M;
    final double maxM;
    final long resets;
    final String worldRefusal;
    final double recentP99M;
    final long inputsOffTick;

    Prediction(boolean predicting, int samples, double p50M, double p99M, double maxM,
        double recentP99M, long inputsOffTick, long resets, String worldRefusal) {
      this.inputsOffTick = inputsOffTick;
      this.recentP99M = recentP99M;
      this.predicting = predicting;
      this.samples = samples;
      this.p50M = p50M;
      this.p99M = p99M;
      this.maxM = maxM;
      this.resets = resets;
      this.worldRefusal = worldRefusal;
    }
  }

  GameStats(double periodS, double rttMs, double snapshotsPerSecond, double snapshotsLostPerSecond,
      double bytesInPerSecond, double bytesOutPerSecond, double firstSnapshotAfterMs,
      long snapshotsReceived, long snapshotsLost, long snapshotsSkipped, long[] payloadRefusals,
      long[] snapshotRejections, long[] datagramDrops, Prediction prediction) {
    this.prediction = prediction;
    this.periodS = periodS;
    this.rttMs = rttMs;
    this.snapshotsPerSecond = snapshotsPerSecond;
    this.snapshotsLostPerSecond = snapshotsLostPerSecond;
    this.bytesInPerSecond = bytesInPerSecond;
    this.bytesOutPerSecond = bytesOutPerSecond;
    this.firstSnapshotAfterMs = firstSnapshotAfterMs;
    this.snapshotsReceived = snapshotsReceived;
    this.snapshotsLost = snapshotsLost;
    this.snapshotsSkipped = snapshotsSkipped;
    this.payloadRefusals = payloadRefusals;
    this.snapshotRejections = snapshotRejections;
    this.datagramDrops = datagramDrops;
  }

  /** Whether the own player is predicted (the join reply's collision world was usable). */
  public boolean predicting() {
    return prediction.predicting;
  }

  /** Prediction errors measured this period (one per newly acknowledged input). */
  public int predictionErrorSamples() {
    return prediction.samples;
  }

  /** Median prediction error this period, m (0 without samples). */
  public double predictionErrorP50M() {
    return prediction.p50M;
  }

  /** 99th-percentile prediction error this period (nearest rank), m. */
  public double predictionErrorP99M() {
    return prediction.p99M;
  }

  /**
   * 99th-percentile prediction error (nearest rank) over the newest 8192 acknowledged inputs of
   * this connection, about two minutes at 60 Hz, m: the figure of a whole play.
   */
  public double predictionErrorRecentP99M() {
    return prediction.recentP99M;
  }

  /**
   * Ticks this period at which the server did not apply this client's next input in order (its
   * jitter buffer repeated one while the next was late, or skipped some after a burst): each moves
   * the player by up to max_speed · dt away from the prediction. 0 on a clean link.
   */
  public long inputsOffTick() {
    return prediction.inputsOffTick;
  }

  /** Largest prediction error this period, m. */
  public double predictionErrorMaxM() {
    return prediction.maxM;
  }

  /** Re-seeds of the prediction since the connection (spawns, teleports), not counted as error. */
  public long predictionResets() {
    return prediction.resets;
  }

  /**
   * Why the join reply's collision world was refused (a {@code WorldRefusal} counter name, e.g.
   * "bad_mesh"), so nothing is predicted; null when it was usable or absent.
   */
  public String collisionWorldRefusal() {
    return prediction.worldRefusal;
  }

  /** The period these rates are over, s. */
  public double periodS() {
    return periodS;
  }

  /** Smoothed round trip, ms (0 before the first ack). */
  public double rttMs() {
    return rttMs;
  }

  /** Snapshots accepted per second. */
  public double snapshotsPerSecond() {
    return snapshotsPerSecond;
  }

  /** Snapshots lost (gaps in the ticks) per second. */
  public double snapshotsLostPerSecond() {
    return snapshotsLostPerSecond;
  }

  /** Datagram bytes received per second (UDP payloads). */
  public double bytesInPerSecond() {
    return bytesInPerSecond;
  }

  /** Datagram bytes sent per second (UDP payloads). */
  public double bytesOutPerSecond() {
    return bytesOutPerSecond;
  }

  /** From the handshake's completion to the first snapshot, ms; -1 before it. */
  public double firstSnapshotAfterMs() {
    return firstSnapshotAfterMs;
  }

  /** Snapshots accepted since the start. */
  public long snapshotsReceived() {
    return snapshotsReceived;
  }

  /** Snapshots lost since the start. */
  public long snapshotsLost() {
    return snapshotsLost;
  }

  /** Snapshots received but not delivered since the start: the listener was behind. */
  public long snapshotsSkipped() {
    return snapshotsSkipped;
  }

  /** Payloads or events refused since the start for {@code reason}. */
  public long refusals(PayloadRefusal reason) {
    return payloadRefusals[reason.ordinal()];
  }

  /** Snapshots the decoder refused since the start for {@code reason}. */
  public long rejections(SnapshotRejection reason) {
    return snapshotRejections[reason.ordinal()];
  }

  /** Datagrams the transport dropped since the start for {@code reason}. */
  public long drops(DropReason reason) {
    return datagramDrops[reason.ordinal()];
  }

  @Override
  public String toString() {
    return String.format(java.util.Locale.ROOT,
        "GameStats{rtt %.1f ms, %.1f snapshots/s, %.1f lost/s, in %.0f B/s, out %.0f B/s, "
            + "first snapshot after %.0f ms, %d received, %d lost, prediction error "
            + "p50 %.4f p99 %.4f max %.4f m of %d%s}",
        rttMs, snapshotsPerSecond, snapshotsLostPerSecond, bytesInPerSecond, bytesOutPerSecond,
        firstSnapshotAfterMs, snapshotsReceived, snapshotsLost, prediction.p50M, prediction.p99M,
        prediction.maxM, prediction.samples,
        prediction.predicting                 ? ""
            : prediction.worldRefusal != null ? ", not predicting: " + prediction.worldRefusal
                                              : ", not predicting");
  }
}
