#include "ricochet/loadtest/server_tracker.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "report_files.h"
#include "ricochet/tools/json_text.h"

namespace ricochet::loadtest {

namespace {

double safe_ratio(double numerator, double denominator) {
  return denominator > 0 ? numerator / denominator : 0.0;
}

/// The busy share of one core over the pairs of consecutive points that both have the counter
/// `field` and where it did not go back, %; -1 when no pair has it.
double cpu_percent_over(const std::vector<ServerPoint>& points, std::size_t base, std::size_t last,
                        double ServerPoint::*field) {
  double busy_s = 0;
  double wall_s = 0;
  for (std::size_t i = base + 1; i <= last && i < points.size(); ++i) {
    const double from = points[i - 1].*field;
    const double to = points[i].*field;
    if (from < 0 || to < from) continue;
    busy_s += to - from;
    wall_s += points[i].t_s - points[i - 1].t_s;
  }
  return wall_s > 0 ? busy_s / wall_s * 100 : -1;
}

void number(std::string& out, const char* key, double value) {
  if (!std::isfinite(value)) value = 0;
  char text[64];
  std::snprintf(text, sizeof text, ",\"%s\":%.6g", key, value);
  out += text;
}

}  // namespace

ServerTracker::ServerTracker(std::string label, ServerProc proc, bool loopback, int pid,
                             Count count)
    : label_(std::move(label)),
      proc_(proc),
      loopback_(loopback),
      pid_(pid),
      count_(std::move(count)) {}

int ServerTracker::proc_pid() const {
  if (proc_ == ServerProc::Off || !loopback_ || proc_given_up_) return 0;
  return pid_;
}

const ServerPoint& ServerTracker::latest() const {
  static const ServerPoint none;
  return points_.empty() ? none : points_.back();
}

const ServerPoint& ServerTracker::observe(double t_s, const std::optional<ServerFigures>& figures,
                                          const std::optional<ProcSample>& proc) {
  ServerPoint point;
  point.t_s = t_s;
  const bool wanted_proc = proc_pid() > 0;  // what the caller was asked to read
  if (figures) {
    point.ok = true;
    point.matches = figures->matches;
    point.players = figures->players;
    point.tick = figures->worst_tick();
    double p99_sum = 0;
    int with_players = 0;
    for (const auto& [id, match] : figures->by_match) {
      if (match.connected == 0) continue;
      p99_sum += match.tick.p99_ms;
      ++with_players;
    }
    point.tick_p99_mean_ms = safe_ratio(p99_sum, with_players);
    point.overruns = figures->overruns;
    point.dropped_steps = figures->dropped_steps;
    point.packets_in = figures->packets_in;
    point.packets_out = figures->packets_out;
    point.phase_seconds = figures->phase_seconds;
    point.placement_tickets = figures->placement_tickets;
    point.cpu_s = figures->cpu_seconds;
    if (figures->resident_bytes >= 0) point.rss_mb = figures->resident_bytes / 1e6;
    for (int i = 0; i < figures->bad_values; ++i) count_("metrics_bad_value");
    if (point.cpu_s < 0) count_("server_cpu_missing");
    if (pid_ == 0) pid_ = figures->pid;
  }
  if (proc) {
    point.cpu_s_proc = proc->cpu_s;
    point.rss_mb_proc = proc->rss_bytes / 1e6;
  } else if (wanted_proc) {
    // auto: the entry did not read (another namespace, another user, gone): /metrics only.
    count_("server_proc_unreadable");
    proc_given_up_ = true;
  }
  if (!points_.empty()) {
    const ServerPoint& previous = points_.back();
    const double wall = t_s - previous.t_s;
    if (point.cpu_s >= 0 && previous.cpu_s >= 0) {
      if (point.cpu_s < previous.cpu_s) {
        count_("server_cpu_reset");  // a restarted server: no rate over this interval
      } else if (wall > 0) {
        point.cpu_percent = (point.cpu_s - previous.cpu_s) / wall * 100;
      }
    }
    if (point.cpu_s_proc >= 0 && previous.cpu_s_proc >= 0 && wall > 0 &&
        point.cpu_s_proc >= previous.cpu_s_proc) {
      point.cpu_percent_proc = (point.cpu_s_proc - previous.cpu_s_proc) / wall * 100;
    }
  }
  points_.push_back(std::move(point));
  return points_.back();
}

ServerWindow ServerTracker::window(double from_t_s, double to_t_s) const {
  ServerWindow out;
  out.label = label_;
  std::size_t first = 0;
  while (first < points_.size() && points_[first].t_s < from_t_s) ++first;
  if (first >= points_.size() || points_[first].t_s > to_t_s) return out;
  std::size_t last = first;
  while (last + 1 < points_.size() && points_[last + 1].t_s <= to_t_s) ++last;
  const std::size_t base = first > 0 ? first - 1 : first;
  double p99_mean_sum = 0;
  int scraped = 0;
  const ServerPoint* first_ok = nullptr;
  const ServerPoint* last_ok = nullptr;
  for (std::size_t i = first; i <= last; ++i) {
    const ServerPoint& p = points_[i];
    out.rss_mb = std::max(out.rss_mb, p.rss_mb);
    out.rss_mb_proc = std::max(out.rss_mb_proc, p.rss_mb_proc);
    if (!p.ok) continue;
    out.tick = out.tick.worst_with(p.tick);
    p99_mean_sum += p.tick_p99_mean_ms;
    ++scraped;
    last_ok = &p;
  }
  for (std::size_t i = base; i <= last; ++i) {
    if (points_[i].ok) {
      first_ok = &points_[i];
      break;
    }
  }
  out.scraped = scraped > 0;
  out.tick_p99_mean_ms = safe_ratio(p99_mean_sum, scraped);
  out.cpu_percent = cpu_percent_over(points_, base, last, &ServerPoint::cpu_s);
  out.cpu_percent_proc = cpu_percent_over(points_, base, last, &ServerPoint::cpu_s_proc);
  if (first_ok && last_ok && first_ok != last_ok) {
    out.matches = last_ok->matches;
    out.players = last_ok->players;
    const double wall = last_ok->t_s - first_ok->t_s;
    out.overruns = std::max(0.0, last_ok->overruns - first_ok->overruns);
    out.dropped_steps = std::max(0.0, last_ok->dropped_steps - first_ok->dropped_steps);
    out.packets_in_per_s =
        std::max(0.0, safe_ratio(last_ok->packets_in - first_ok->packets_in, wall));
    out.packets_out_per_s =
        std::max(0.0, safe_ratio(last_ok->packets_out - first_ok->packets_out, wall));
    for (const auto& [phase, seconds] : last_ok->phase_seconds) {
      const auto before = first_ok->phase_seconds.find(phase);
      const double start = before == first_ok->phase_seconds.end() ? 0.0 : before->second;
      out.phase_percent[phase] = safe_ratio(seconds - start, wall) * 100;
    }
  } else if (last_ok) {
    out.matches = last_ok->matches;
    out.players = last_ok->players;
  }
  return out;
}

std::map<std::string, double> ServerTracker::placement_tickets(double from_t_s,
                                                               double to_t_s) const {
  const ServerPoint* from = nullptr;
  const ServerPoint* to = nullptr;
  for (const ServerPoint& point : points_) {
    if (!point.ok || point.t_s > to_t_s) continue;
    if (!from || point.t_s <= from_t_s) from = &point;
    to = &point;
  }
  std::map<std::string, double> out;
  if (!from || !to) return out;
  for (const auto& [result, count] : to->placement_tickets) {
    const auto before = from->placement_tickets.find(result);
    const double start = before == from->placement_tickets.end() ? 0.0 : before->second;
    if (count >= start) out[result] = count - start;
  }
  return out;
}

std::string ServerWindow::to_json() const {
  std::string out = "{\"server\":" + tools::json_string(label);
  out += std::string(",\"scraped\":") + (scraped ? "true" : "false");
  number(out, "matches", matches);
  number(out, "players", players);
  number(out, "tick_ms_p50", tick.p50_ms);
  number(out, "tick_ms_p95", tick.p95_ms);
  number(out, "tick_ms_p99", tick.p99_ms);
  number(out, "tick_ms_max", tick.max_ms);
  number(out, "tick_ms_p99_mean_match", tick_p99_mean_ms);
  number(out, "overruns", overruns);
  number(out, "dropped_steps", dropped_steps);
  number(out, "cpu_percent", cpu_percent);
  number(out, "rss_mb", rss_mb);
  number(out, "cpu_percent_proc", cpu_percent_proc);
  number(out, "rss_mb_proc", rss_mb_proc);
  number(out, "packets_in_per_s", packets_in_per_s);
  number(out, "packets_out_per_s", packets_out_per_s);
  out += ",\"phase_percent\":" + percent_object_json(phase_percent);
  out += ",\"placement_tickets\":{";
  for (auto it = placement_tickets.begin(); it != placement_tickets.end(); ++it) {
    if (it != placement_tickets.begin()) out += ',';
    out += tools::json_string(it->first) + ':' + std::to_string(std::llround(it->second));
  }
  return out + "}}";
}

}  // namespace ricochet::loadtest
