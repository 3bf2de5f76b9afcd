#include "ricochet/loadtest/run_record.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "report_files.h"
#include "ricochet/loadtest/capacity.h"
#include "ricochet/tools/json_text.h"

namespace ricochet::loadtest {

namespace {

/// `"key":value` with a finite number (JSON has no NaN or infinity: those become 0).
void field(std::string& out, const char* key, double value) {
  if (!std::isfinite(value)) value = 0;
  char text[64];
  std::snprintf(text, sizeof text, "\"%s\":%.6g,", key, value);
  out += text;
}

}  // namespace

void StepSummary::total_servers() {
  const auto cpu_of = [](const ServerWindow& w) {
    return w.cpu_percent >= 0 ? w.cpu_percent : w.cpu_percent_proc;
  };
  const auto rss_of = [](const ServerWindow& w) {
    return w.rss_mb >= 0 ? w.rss_mb : w.rss_mb_proc;
  };
  overruns = 0;
  dropped_steps = 0;
  server_packets_in_per_s = 0;
  server_packets_out_per_s = 0;
  server_phase_percent.clear();
  servers_cpu_percent_total = 0;
  servers_rss_mb_total = 0;
  server_rss_mb = 0;
  const ServerWindow* busiest = nullptr;
  for (const ServerWindow& window : servers) {
    overruns += window.overruns;
    dropped_steps += window.dropped_steps;
    server_packets_in_per_s += window.packets_in_per_s;
    server_packets_out_per_s += window.packets_out_per_s;
    for (const auto& [phase, percent] : window.phase_percent)
      server_phase_percent[phase] += percent;
    servers_cpu_percent_total += std::max(0.0, cpu_of(window));
    servers_rss_mb_total += std::max(0.0, rss_of(window));
    server_rss_mb = std::max(server_rss_mb, rss_of(window));
    if (!busiest || cpu_of(window) > cpu_of(*busiest)) busiest = &window;
  }
  server_cpu_percent = 0;
  server_cpu_source = "none";
  server_cpu_percent_proc = -1;
  server_rss_mb_proc = -1;
  if (!busiest) return;
  if (busiest->cpu_percent >= 0) {
    server_cpu_percent = busiest->cpu_percent;
    server_cpu_source = "metrics";
  } else if (busiest->cpu_percent_proc >= 0) {
    server_cpu_percent = busiest->cpu_percent_proc;
    server_cpu_source = "proc";
  }
  server_cpu_percent_proc = busiest->cpu_percent_proc;
  server_rss_mb_proc = busiest->rss_mb_proc;
}

bool StepSummary::meets_capacity() const {
  return capacity_shortfalls(*this).empty();
}

bool StepSummary::generator_saturated() const {
  return generator_cpu_percent >= kGeneratorSaturatedCpuPercent;
}

std::string StepSummary::to_json(bool samples) const {
  std::string out = "{";
  field(out, "bots", bots);
  field(out, "bots_connected", bots_connected);
  field(out, "bots_gave_up", bots_gave_up);
  field(out, "matches", matches);
  field(out, "measured_s", measured_s);
  field(out, "ramp_s", ramp_s);
  field(out, "server_tick_ms_p50", server_tick.p50_ms);
  field(out, "server_tick_ms_p95", server_tick.p95_ms);
  field(out, "server_tick_ms_p99", server_tick.p99_ms);
  field(out, "server_tick_ms_max", server_tick.max_ms);
  field(out, "server_tick_ms_p99_mean_match", server_tick_ms_p99_mean);
  field(out, "overruns", overruns);
  field(out, "dropped_steps", dropped_steps);
  field(out, "snapshot_loss", snapshot_loss);
  field(out, "snapshots_per_s_per_bot", snapshots_per_s_per_bot);
  field(out, "rtt_ms_p50", rtt_ms_p50);
  field(out, "rtt_ms_p99", rtt_ms_p99);
  field(out, "kbps_in_per_client", kbps_in_per_client);
  field(out, "kbps_out_per_client", kbps_out_per_client);
  field(out, "kbps_in_total", kbps_in_total);
  field(out, "kbps_out_total", kbps_out_total);
  field(out, "server_cpu_percent", server_cpu_percent);
  field(out, "server_rss_mb", server_rss_mb);
  out += "\"server_cpu_source\":" + tools::json_string(server_cpu_source) + ',';
  if (server_cpu_percent_proc >= 0) {
    // Both readings of the same server over the same window, and how far apart they are.
    field(out, "server_cpu_percent_proc", server_cpu_percent_proc);
    field(out, "server_rss_mb_proc", server_rss_mb_proc);
    field(out, "server_cpu_proc_minus_metrics", server_cpu_percent_proc - server_cpu_percent);
  }
  field(out, "servers_cpu_percent_total", servers_cpu_percent_total);
  field(out, "servers_rss_mb_total", servers_rss_mb_total);
  field(out, "generator_cpu_percent", generator_cpu_percent);
  field(out, "generator_rss_mb", generator_rss_mb);
  field(out, "server_packets_in_per_s", server_packets_in_per_s);
  field(out, "server_packets_out_per_s", server_packets_out_per_s);
  field(out, "connect_ms_p50", connect_ms_p50);
  field(out, "connect_ms_p99", connect_ms_p99);
  field(out, "connect_ms_max", connect_ms_max);
  field(out, "placement_ms_p50", placement_ms_p50);
  field(out, "placement_ms_p99", placement_ms_p99);
  field(out, "placement_ms_max", placement_ms_max);
  out += "\"bots_placed\":{";
  for (auto it = bots_placed.begin(); it != bots_placed.end(); ++it) {
    if (it != bots_placed.begin()) out += ',';
    out += tools::json_string(it->first) + ':' + std::to_string(it->second);
  }
  out += "},";
  field(out, "snapshots_received", snapshots_received);
  field(out, "snapshots_lost", snapshots_lost);
  if (samples) {
    for (const auto& [key, values] : {std::pair{"rtt_ms_samples", &rtt_ms_samples},
                                      std::pair{"connect_ms_samples", &connect_ms_samples},
                                      std::pair{"placement_ms_samples", &placement_ms_samples}}) {
      out += '"';
      out += key;
      out += "\":[";
      char text[32];
      for (std::size_t i = 0; i < values->size(); ++i) {
        const double value = (*values)[i];
        std::snprintf(text, sizeof text, "%s%.5g", i ? "," : "",
                      std::isfinite(value) ? value : 0.0);
        out += text;
      }
      out += "],";
    }
  }
  out += "\"meets_capacity\":";
  out += meets_capacity() ? "true" : "false";
  out += ",\"generator_saturated\":";
  out += generator_saturated() ? "true" : "false";
  out += ",\"server_phase_percent\":" + percent_object_json(server_phase_percent);
  out += ",\"servers\":[";
  for (std::size_t i = 0; i < servers.size(); ++i) {
    if (i > 0) out += ',';
    out += servers[i].to_json();
  }
  out += ']';
  out += ",\"errors\":{";
  bool first = true;
  for (const auto& [kind, n] : errors) {
    if (!first) out += ',';
    first = false;
    out += tools::json_string(kind) + ':' + std::to_string(n);
  }
  out += "}}";
  return out;
}

}  // namespace ricochet::loadtest
