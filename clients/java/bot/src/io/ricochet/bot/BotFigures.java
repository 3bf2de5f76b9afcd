package io.ricochet.bot;

import io.ricochet.client.GameStats;
import java.util.ArrayList;
import java.util.Collections;
import java.util.List;
import java.util.Locale;

/**
 * What one bot measured (or, {@link #merge}d, all of them), printed as JSON with ricochet-bot's
 * field names where they mean the same (tools/bot/README.md): round trip, snapshots, bytes each
 * way, kills and deaths, the prediction error. Filled on the bots' listener thread; read there.
 */
final class BotFigures {
  double connectedS;
  final List<Double> rttMs = new ArrayList<>();
  long snapshots;
  long snapshotsLost;
  long snapshotsSkipped;
  double bytesIn;
  double bytesOut;
  double firstSnapshotMs = -1;
  int kills;
  int deaths;
  int killEvents;
  int hitsDealt;
  int reconnects;
  int scoreResyncs;
  int matches;
  long predictionSamples;
  double predictionErrorP99M;
  double predictionErrorMaxM;
  long predictionResets;
  /**
   * Results of the matches it finished: this player's kills, deaths and score as the server said.
   */
  int resultKills;
  int resultDeaths;
  int resultScore;

  /** One {@link io.ricochet.client.GameListener#onStats} period of a connection. */
  void addPeriod(GameStats stats) {
    if (stats.rttMs() > 0) rttMs.add(stats.rttMs());
    bytesIn += stats.bytesInPerSecond() * stats.periodS();
    bytesOut += stats.bytesOutPerSecond() * stats.periodS();
    predictionSamples += stats.predictionErrorSamples();
    predictionErrorMaxM = Math.max(predictionErrorMaxM, stats.predictionErrorMaxM());
  }

  /**
   * Adds what a game connection counted from its start to its end ({@code last}: its newest
   * figures): lost and skipped snapshots, prediction resets, and the prediction's p99 over its
   * newest inputs (the largest of the connections').
   */
  void addConnection(GameStats last) {
    snapshotsLost += last.snapshotsLost();
    snapshotsSkipped += last.snapshotsSkipped();
    predictionResets += last.predictionResets();
    predictionErrorP99M = Math.max(predictionErrorP99M, last.predictionErrorRecentP99M());
  }

  /** A copy (its round-trip samples too). */
  BotFigures copy() {
    BotFigures copy = new BotFigures();
    copy.merge(this);
    return copy;
  }

  /** Adds {@code other}'s counts; means and percentiles of the round trip over both samples. */
  void merge(BotFigures other) {
    connectedS += other.connectedS;
    rttMs.addAll(other.rttMs);
    snapshots += other.snapshots;
    snapshotsLost += other.snapshotsLost;
    snapshotsSkipped += other.snapshotsSkipped;
    bytesIn += other.bytesIn;
    bytesOut += other.bytesOut;
    if (other.firstSnapshotMs >= 0) {
      firstSnapshotMs = firstSnapshotMs < 0 ? other.firstSnapshotMs
                                            : Math.max(firstSnapshotMs, other.firstSnapshotMs);
    }
    kills += other.kills;
    deaths += other.deaths;
    killEvents += other.killEvents;
    hitsDealt += other.hitsDealt;
    reconnects += other.reconnects;
    scoreResyncs += other.scoreResyncs;
    matches += other.matches;
    predictionSamples += other.predictionSamples;
    predictionErrorP99M = Math.max(predictionErrorP99M, other.predictionErrorP99M);
    predictionErrorMaxM = Math.max(predictionErrorMaxM, other.predictionErrorMaxM);
    predictionResets += other.predictionResets;
    resultKills += other.resultKills;
    resultDeaths += other.resultDeaths;
    resultScore += other.resultScore;
  }

  /** One JSON object; rates are per second of connection. */
  String toJson() {
    double perS = connectedS > 0 ? 1 / connectedS : 0;
    double expected = snapshots + snapshotsLost;
    List<Double> sorted = new ArrayList<>(rttMs);
    Collections.sort(sorted);
    double mean = 0;
    for (double each : sorted) mean += each;
    mean = sorted.isEmpty() ? 0 : mean / sorted.size();
    return String.format(Locale.ROOT,
        "{\"connected_s\":%.3f,\"rtt_ms_mean\":%.3f,\"rtt_ms_p50\":%.3f,\"rtt_ms_p99\":%.3f,"
            + "\"rtt_samples\":%d,\"snapshots\":%d,\"snapshots_per_s\":%.2f,"
            + "\"snapshots_lost\":%d,\"snapshot_loss\":%.5f,\"snapshots_skipped\":%d,"
            + "\"bytes_in_per_s\":%.1f,\"bytes_out_per_s\":%.1f,\"bytes_in\":%d,\"bytes_out\":%d,"
            + "\"first_snapshot_ms\":%.3f,\"kills\":%d,\"deaths\":%d,\"kill_events\":%d,"
            + "\"hits_dealt\":%d,\"reconnects\":%d,\"score_resyncs\":%d,\"matches\":%d,"
            + "\"result_kills\":%d,\"result_deaths\":%d,\"result_score\":%d,"
            + "\"prediction_samples\":%d,\"prediction_error_m_p99\":%.6f,"
            + "\"prediction_error_m_max\":%.6f,\"prediction_resets\":%d}",
        connectedS, mean, percentile(sorted, 50), percentile(sorted, 99), sorted.size(), snapshots,
        snapshots * perS, snapshotsLost, expected > 0 ? snapshotsLost / expected : 0,
        snapshotsSkipped, bytesIn * perS, bytesOut * perS, Math.round(bytesIn),
        Math.round(bytesOut), firstSnapshotMs, kills, deaths, killEvents, hitsDealt, reconnects,
        scoreResyncs, matches, resultKills, resultDeaths, resultScore, predictionSamples,
        predictionErrorP99M, predictionErrorMaxM, predictionResets);
  }

  /** The nearest-rank percentile {@code p} of {@code sorted} (stats/percentile.h); 0 if empty. */
  static double percentile(List<Double> sorted, double p) {
    if (sorted.isEmpty()) return 0;
    int rank = (int) Math.ceil(p / 100 * sorted.size());
    return sorted.get(Math.max(1, Math.min(rank, sorted.size())) - 1);
  }
}
