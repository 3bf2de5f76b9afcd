#include "ricochet/bot/bot_metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "ricochet/stats/summary.h"

namespace ricochet::bot {

void SnapshotGapCounter::on_snapshot(std::uint32_t tick) {
  ++received_;
  if (has_last_ && tick > last_tick_) {
    const double steps = std::round(static_cast<double>(tick - last_tick_) / interval_);
    if (steps > 1) lost_ += static_cast<std::uint64_t>(steps - 1);
  }
  has_last_ = true;
  last_tick_ = tick;
}

void BotMetrics::add_transport(const proto::TransportCounters& counters, double connected_for_s) {
  packets_in += counters.packets_in;
  packets_out += counters.packets_out;
  bytes_in += counters.bytes_in;
  bytes_out += counters.bytes_out;
  transport_drops += counters.dropped_total();
  connected_s += connected_for_s;
}

void BotMetrics::merge(const BotMetrics& other) {
  packets_in += other.packets_in;
  packets_out += other.packets_out;
  bytes_in += other.bytes_in;
  bytes_out += other.bytes_out;
  connected_s += other.connected_s;
  snapshots += other.snapshots;
  snapshots_lost += other.snapshots_lost;
  server_packets += other.server_packets;
  server_packets_missing += other.server_packets_missing;
  rtt_ms.insert(rtt_ms.end(), other.rtt_ms.begin(), other.rtt_ms.end());
  if (other.first_snapshot_ms >= 0) {
    first_snapshot_ms = std::max(first_snapshot_ms, other.first_snapshot_ms);
  }
  last_reconnect_ms = std::max(last_reconnect_ms, other.last_reconnect_ms);
  placement_ms.insert(placement_ms.end(), other.placement_ms.begin(), other.placement_ms.end());
  bad_payloads += other.bad_payloads;
  bad_events += other.bad_events;
  snapshots_refused += other.snapshots_refused;
  bad_control += other.bad_control;
  transport_drops += other.transport_drops;
  send_failures += other.send_failures;
  kills += other.kills;
  deaths += other.deaths;
  kill_events += other.kill_events;
  hits_dealt += other.hits_dealt;
  reconnects += other.reconnects;
  resumes += other.resumes;
  score_resyncs += other.score_resyncs;
  matches += other.matches;
  inputs_sent += other.inputs_sent;
  weapon_switches += other.weapon_switches;
  prediction_error_m.insert(prediction_error_m.end(), other.prediction_error_m.begin(),
                            other.prediction_error_m.end());
  prediction_resets += other.prediction_resets;
  prediction_replayed += other.prediction_replayed;
  own_travelled_m += other.own_travelled_m;
  worlds_refused += other.worlds_refused;
  sim_dropped += other.sim_dropped;
  sim_duplicated += other.sim_duplicated;
  sim_reordered += other.sim_reordered;
}

std::string BotMetrics::to_json() const {
  const double per_s = connected_s > 0 ? 1.0 / connected_s : 0.0;
  const double expected = static_cast<double>(snapshots + snapshots_lost);
  const double loss = expected > 0 ? static_cast<double>(snapshots_lost) / expected : 0.0;
  const double packet_loss = server_packets > 0 ? static_cast<double>(server_packets_missing) /
                                                      static_cast<double>(server_packets)
                                                : 0.0;
  const stats::Summary rtt = stats::summarize(rtt_ms);
  char text[2048];
  std::snprintf(
      text, sizeof text,
      "{\"connected_s\":%.3f,\"rtt_ms_mean\":%.3f,\"rtt_ms_p50\":%.3f,\"rtt_ms_p99\":%.3f,"
      "\"rtt_samples\":%zu,\"snapshots\":%llu,\"snapshots_per_s\":%.2f,\"snapshots_lost\":%llu,"
      "\"snapshot_loss\":%.5f,\"packet_loss\":%.5f,\"server_packets_missing\":%llu,"
      "\"packets_in_per_s\":%.2f,\"packets_out_per_s\":%.2f,"
      "\"bytes_in_per_s\":%.1f,\"bytes_out_per_s\":%.1f,\"packets_in\":%llu,\"packets_out\":%llu,"
      "\"bytes_in\":%llu,\"bytes_out\":%llu,\"first_snapshot_ms\":%.3f,"
      "\"last_reconnect_ms\":%.3f,\"kills\":%d,\"deaths\":%d,\"kill_events\":%d,"
      "\"hits_dealt\":%d,\"reconnects\":%d,\"resumes\":%d,\"score_resyncs\":%d,\"matches\":%d,"
      "\"inputs_sent\":%"
      "llu,"
      "\"weapon_switches\":%llu,\"bad_payloads\":%llu,\"bad_events\":%llu,"
      "\"snapshots_refused\":%llu,\"bad_control\":%llu,\"transport_drops\":%llu,"
      "\"send_failures\":%llu}",
      connected_s, rtt.mean, rtt.p50, rtt.p99, rtt.count,
      static_cast<unsigned long long>(snapshots), static_cast<double>(snapshots) * per_s,
      static_cast<unsigned long long>(snapshots_lost), loss, packet_loss,
      static_cast<unsigned long long>(server_packets_missing),
      static_cast<double>(packets_in) * per_s, static_cast<double>(packets_out) * per_s,
      static_cast<double>(bytes_in) * per_s, static_cast<double>(bytes_out) * per_s,
      static_cast<unsigned long long>(packets_in), static_cast<unsigned long long>(packets_out),
      static_cast<unsigned long long>(bytes_in), static_cast<unsigned long long>(bytes_out),
      first_snapshot_ms, last_reconnect_ms, kills, deaths, kill_events, hits_dealt, reconnects,
      resumes, score_resyncs, matches, static_cast<unsigned long long>(inputs_sent),
      static_cast<unsigned long long>(weapon_switches),
      static_cast<unsigned long long>(bad_payloads), static_cast<unsigned long long>(bad_events),
      static_cast<unsigned long long>(snapshots_refused),
      static_cast<unsigned long long>(bad_control),
      static_cast<unsigned long long>(transport_drops),
      static_cast<unsigned long long>(send_failures));
  std::string out = text;
  out.pop_back();  // the closing brace: the prediction and simulator figures follow
  const stats::Summary error = stats::summarize(prediction_error_m);
  std::snprintf(text, sizeof text,
                ",\"prediction_samples\":%zu,\"prediction_error_m_p50\":%.6f,"
                "\"prediction_error_m_p99\":%.6f,\"prediction_error_m_max\":%.6f,"
                "\"prediction_resets\":%llu,\"prediction_replayed\":%llu,\"own_travelled_m\":%.2f,"
                "\"worlds_refused\":%llu,\"sim_dropped\":%llu,\"sim_duplicated\":%llu,"
                "\"sim_reordered\":%llu}",
                error.count, error.p50, error.p99, error.max,
                static_cast<unsigned long long>(prediction_resets),
                static_cast<unsigned long long>(prediction_replayed), own_travelled_m,
                static_cast<unsigned long long>(worlds_refused),
                static_cast<unsigned long long>(sim_dropped),
                static_cast<unsigned long long>(sim_duplicated),
                static_cast<unsigned long long>(sim_reordered));
  out += text;
  out.pop_back();
  const stats::Summary placement = stats::summarize(placement_ms);
  std::snprintf(text, sizeof text,
                ",\"placements\":%zu,\"placement_ms_p50\":%.3f,\"placement_ms_max\":%.3f}",
                placement.count, placement.p50, placement.max);
  return out + text;
}

}  // namespace ricochet::bot
