#include "ricochet/loadtest/soak_record.h"

#include <algorithm>

#include "ricochet/stats/percentile.h"

namespace ricochet::loadtest {

namespace {

constexpr double kSecondsPerHour = 3600;

}  // namespace

SoakSummary summarise_soak(const std::vector<SoakSample>& samples, double warmup_s,
                           const FlatnessBounds& bounds) {
  SoakSummary out;
  out.samples = static_cast<int>(samples.size());
  if (samples.empty()) {
    out.flatness = judge_flatness({}, warmup_s, bounds);
    return out;
  }
  const SoakSample& last = samples.back();
  out.duration_s = last.t_s;
  out.sign_ins = last.sign_ins;
  out.new_accounts = last.new_accounts;
  out.departures = last.departures;
  out.matches_finished = last.matches_finished;
  out.errors = last.errors;

  std::vector<FlatnessPoint> points;
  std::vector<double> db_t;
  std::vector<double> db_mib;
  std::vector<double> tick_p99;
  std::vector<double> playing;
  const SoakSample* first_after = nullptr;
  for (const SoakSample& s : samples) {
    if (!s.server_ok) ++out.scrapes_failed;
    if (s.db_mib >= 0) {
      if (out.db_mib_first < 0) out.db_mib_first = s.db_mib;
      out.db_mib_last = s.db_mib;
      db_t.push_back(s.t_s / kSecondsPerHour);
      db_mib.push_back(s.db_mib);
    }
    if (s.t_s < warmup_s) continue;
    if (!first_after) first_after = &s;
    playing.push_back(s.playing);
    if (s.server_ok && s.tick_p99_ms > 0) {
      tick_p99.push_back(s.tick_p99_ms);
      out.tick_max_ms_max = std::max(out.tick_max_ms_max, s.tick_max_ms);
    }
    // A point needs both figures: a failed scrape or /proc read is left out, not read as 0.
    if (s.rss_mib < 0 || s.open_fds < 0) continue;
    points.push_back({s.t_s, s.rss_mib, s.open_fds});
    if (out.rss_mib_first < 0) {
      out.rss_mib_first = s.rss_mib;
      out.fds_first = s.open_fds;
    }
    out.rss_mib_last = s.rss_mib;
    out.fds_last = s.open_fds;
    out.rss_mib_max = std::max(out.rss_mib_max, s.rss_mib);
    out.fds_max = std::max(out.fds_max, s.open_fds);
  }
  out.flatness = judge_flatness(points, warmup_s, bounds);
  out.db_mib_per_hour = least_squares_slope(db_t, db_mib);
  out.tick_p99_ms_median = stats::percentile(tick_p99, 50);
  out.tick_p99_ms_max = stats::percentile(tick_p99, 100);
  if (!playing.empty()) {
    out.playing_min = static_cast<int>(*std::min_element(playing.begin(), playing.end()));
    out.playing_median = static_cast<int>(stats::percentile(playing, 50));
  }
  if (first_after) {
    const double received = last.snapshots - first_after->snapshots;
    const double lost = last.snapshots_lost - first_after->snapshots_lost;
    out.snapshot_loss = received + lost > 0 ? lost / (received + lost) : 0;
    const double packets = last.server_packets - first_after->server_packets;
    const double missing = last.server_packets_missing - first_after->server_packets_missing;
    out.packet_loss = packets > 0 ? missing / packets : 0;
  }
  return out;
}

}  // namespace ricochet::loadtest
