#include "ricochet/loadtest/merge.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "report_files.h"
#include "ricochet/loadtest/capacity.h"
#include "ricochet/stats/percentile.h"
#include "ricochet/tools/json_text.h"

namespace ricochet::loadtest {

namespace fs = std::filesystem;
using tools::json_string;

namespace {

/// A zero line over the servers' x range, so that a plot whose every value is missing (no server
/// reported its CPU) is drawn empty rather than failing gnuplot.
constexpr const char* kBaseline = ", 'servers.dat' index 0 u 1:(0) w l lc rgb 'gray' notitle\n";

/// Step `index` of every generator as one step.
StepSummary merge_step(const std::vector<GeneratorReport>& generators, std::size_t index) {
  StepSummary out;
  double snapshot_rate_sum = 0;  // snapshots per second per bot, times bots connected
  std::map<std::string, std::size_t> server_at;  // label → index in out.servers
  for (const GeneratorReport& generator : generators) {
    const StepSummary& step = generator.steps[index];
    out.bots += step.bots;
    out.bots_connected += step.bots_connected;
    out.bots_gave_up += step.bots_gave_up;
    out.measured_s = std::max(out.measured_s, step.measured_s);
    out.ramp_s = std::max(out.ramp_s, step.ramp_s);
    out.snapshots_received += step.snapshots_received;
    out.snapshots_lost += step.snapshots_lost;
    snapshot_rate_sum += step.snapshots_per_s_per_bot * step.bots_connected;
    out.kbps_in_total += step.kbps_in_total;
    out.kbps_out_total += step.kbps_out_total;
    out.generator_cpu_percent = std::max(out.generator_cpu_percent, step.generator_cpu_percent);
    out.generator_rss_mb = std::max(out.generator_rss_mb, step.generator_rss_mb);
    out.rtt_ms_samples.insert(out.rtt_ms_samples.end(), step.rtt_ms_samples.begin(),
                              step.rtt_ms_samples.end());
    out.connect_ms_samples.insert(out.connect_ms_samples.end(), step.connect_ms_samples.begin(),
                                  step.connect_ms_samples.end());
    out.placement_ms_samples.insert(out.placement_ms_samples.end(),
                                    step.placement_ms_samples.begin(),
                                    step.placement_ms_samples.end());
    for (const auto& [server, bots] : step.bots_placed) out.bots_placed[server] += bots;
    for (const auto& [kind, n] : step.errors) out.errors[kind] += n;
    // Each server once: from the first generator that scraped it in this step.
    for (const ServerWindow& server : step.servers) {
      const auto [at, added] = server_at.emplace(server.label, out.servers.size());
      if (added) {
        out.servers.push_back(server);
      } else if (!out.servers[at->second].scraped && server.scraped) {
        out.servers[at->second] = server;
      }
    }
  }
  const double connected = std::max(1, out.bots_connected);
  out.snapshots_per_s_per_bot = snapshot_rate_sum / connected;
  out.kbps_in_per_client = out.kbps_in_total / connected;
  out.kbps_out_per_client = out.kbps_out_total / connected;
  const double seen = out.snapshots_received + out.snapshots_lost;
  out.snapshot_loss = seen > 0 ? out.snapshots_lost / seen : 0;
  out.rtt_ms_p50 = stats::percentile(out.rtt_ms_samples, 50);
  out.rtt_ms_p99 = stats::percentile(out.rtt_ms_samples, 99);
  out.connect_ms_p50 = stats::percentile(out.connect_ms_samples, 50);
  out.connect_ms_p99 = stats::percentile(out.connect_ms_samples, 99);
  out.connect_ms_max = stats::percentile(out.connect_ms_samples, 100);
  out.placement_ms_p50 = stats::percentile(out.placement_ms_samples, 50);
  out.placement_ms_p99 = stats::percentile(out.placement_ms_samples, 99);
  out.placement_ms_max = stats::percentile(out.placement_ms_samples, 100);
  double p99_mean_sum = 0;
  int scraped = 0;
  for (const ServerWindow& server : out.servers) {
    if (!server.scraped) continue;
    out.matches += server.matches;
    out.server_tick = out.server_tick.worst_with(server.tick);
    p99_mean_sum += server.tick_p99_mean_ms;
    ++scraped;
  }
  out.server_tick_ms_p99_mean = scraped > 0 ? p99_mean_sum / scraped : 0;
  out.total_servers();
  return out;
}

std::string report_json(const MergedReport& merged, const ReportContext& context) {
  std::string out = "{\"tool\":\"ricochet-loadtest\",\"merged\":true,\"measured_at_utc\":" +
                    json_string(context.measured_at_utc) +
                    ",\"command\":" + json_string(context.command) + ",\"generators\":[";
  for (std::size_t i = 0; i < merged.generators.size(); ++i) {
    const GeneratorReport& g = merged.generators[i];
    const StepSummary& last = g.steps.back();
    char figures[160];
    std::snprintf(figures, sizeof figures,
                  ",\"bots\":%d,\"bots_connected\":%d,\"generator_cpu_percent\":%.6g,"
                  "\"generator_rss_mb\":%.6g}",
                  last.bots, last.bots_connected, last.generator_cpu_percent,
                  last.generator_rss_mb);
    if (i > 0) out += ',';
    out += "{\"source\":";
    out += json_string(g.source);
    out += ",\"measured_at_utc\":";
    out += json_string(g.measured_at_utc);
    out += ",\"command\":";
    out += json_string(g.command);
    out += figures;
  }
  out += "],\"skipped\":[";
  for (std::size_t i = 0; i < merged.skipped.size(); ++i) {
    if (i > 0) out += ',';
    out += "{\"source\":";
    out += json_string(merged.skipped[i].first);
    out += ",\"reason\":";
    out += json_string(merged.skipped[i].second);
    out += '}';
  }
  out += "],\"capacity_bots\":" + std::to_string(capacity_bots(merged.steps)) + ",\"steps\":[";
  for (std::size_t i = 0; i < merged.steps.size(); ++i) {
    if (i > 0) out += ',';
    out += merged.steps[i].to_json(/*samples=*/true);
  }
  out += "],";
  return out + merged.steps.back().to_json().substr(1);  // the last step at the top level
}

/// Per step and server: step bots server cpu_pct rss_mb cpu_pct_proc tick_p99 matches players.
std::string servers_table(const MergedReport& merged, std::vector<std::string>& labels) {
  for (const StepSummary& step : merged.steps) {
    for (const ServerWindow& server : step.servers) {
      if (std::find(labels.begin(), labels.end(), server.label) == labels.end()) {
        labels.push_back(server.label);
      }
    }
  }
  std::string out =
      "# per server (index i): step bots cpu_pct rss_mb cpu_pct_proc tick_p99 "
      "matches players\n";
  char line[160];
  for (const std::string& label : labels) {
    out += "# " + label + "\n";
    for (std::size_t i = 0; i < merged.steps.size(); ++i) {
      for (const ServerWindow& s : merged.steps[i].servers) {
        if (s.label != label) continue;
        std::snprintf(line, sizeof line, "%zu %d %.2f %.2f %.2f %.4f %d %d\n", i + 1,
                      merged.steps[i].bots, s.cpu_percent, s.rss_mb, s.cpu_percent_proc,
                      s.tick.p99_ms, s.matches, s.players);
        out += line;
      }
    }
    out += "\n\n";
  }
  return out;
}

/// Per generator, its last step: index bots connected cpu_pct rss_mb.
std::string generators_table(const MergedReport& merged) {
  std::string out = "# generator bots bots_connected gen_cpu_pct gen_rss_mb\n";
  char line[128];
  for (std::size_t i = 0; i < merged.generators.size(); ++i) {
    const StepSummary& last = merged.generators[i].steps.back();
    std::snprintf(line, sizeof line, "%zu %d %d %.2f %.2f\n", i + 1, last.bots, last.bots_connected,
                  last.generator_cpu_percent, last.generator_rss_mb);
    out += line;
  }
  return out;
}

}  // namespace

std::variant<MergedReport, std::string> merge_reports(std::vector<GeneratorReport> generators) {
  if (generators.empty()) return "no report to merge";
  const std::size_t steps = generators.front().steps.size();
  for (const GeneratorReport& g : generators) {
    if (g.steps.size() != steps) {
      return "the generators ran different steps: " + generators.front().source + " has " +
             std::to_string(steps) + ", " + g.source + " " + std::to_string(g.steps.size()) +
             " (run every generator with the same --sweep)";
    }
  }
  MergedReport out;
  for (std::size_t i = 0; i < steps; ++i) out.steps.push_back(merge_step(generators, i));
  out.generators = std::move(generators);
  return out;
}

std::variant<MergedReport, std::string> merge_directories(const std::vector<std::string>& dirs,
                                                          bool skip_bad) {
  std::vector<GeneratorReport> reports;
  std::vector<std::pair<std::string, std::string>> skipped;
  for (const std::string& dir : dirs) {
    const std::string path = (fs::path(dir) / "report.json").string();
    std::string problem;
    std::error_code error;
    const auto size = fs::file_size(path, error);
    if (error) {
      problem = path + ": cannot read (" + error.message() + ")";
    } else if (size > kMaxReportBytes) {
      problem = path + ": " + std::to_string(size) + " bytes, at most " +
                std::to_string(kMaxReportBytes) + " read";
    } else {
      std::ifstream file(path, std::ios::binary);
      std::ostringstream text;
      text << file.rdbuf();
      auto read = read_generator_report(text.str(), path);
      if (auto* report = std::get_if<GeneratorReport>(&read)) {
        reports.push_back(std::move(*report));
        continue;
      }
      problem = std::get<std::string>(read);
    }
    if (!skip_bad) return problem + " (--skip-bad leaves such a report out)";
    std::fprintf(stderr, "ricochet-loadtest merge: skipped %s\n", problem.c_str());
    skipped.emplace_back(path, problem);
  }
  auto merged = merge_reports(std::move(reports));
  if (auto* out = std::get_if<MergedReport>(&merged)) out->skipped = std::move(skipped);
  return merged;
}

std::string write_merged_report(const MergedReport& merged, const std::string& out, bool plots,
                                const ReportContext& context) {
  const fs::path dir(out);
  std::error_code made;
  fs::create_directories(dir, made);
  if (made) return "cannot create " + dir.string() + ": " + made.message();
  std::vector<std::string> labels;
  std::string error;
  const StepSummary& last = merged.steps.back();
  if (!write_file(dir / "report.json", report_json(merged, context) + "\n", error) ||
      !write_file(dir / "servers.dat", servers_table(merged, labels), error) ||
      !write_file(dir / "generators.dat", generators_table(merged), error) ||
      !write_file(dir / "rtt.dat",
                  distribution_table(last.rtt_ms_samples, "# rtt_ms fraction_of_samples"), error) ||
      !write_file(dir / "connect.dat",
                  distribution_table(last.connect_ms_samples, "# connect_ms fraction_of_bots"),
                  error) ||
      !write_file(dir / "errors.dat", errors_table(last.errors), error)) {
    return error;
  }
  if (!plots) return {};
  std::string titles;
  for (const std::string& label : labels) {
    if (!titles.empty()) titles += ' ';
    titles += label;
  }
  std::string gp =
      std::string(kGnuplotPreamble) + "servers = '" + titles +
      "'\nset datafile missing '-1.00'\nset xlabel 'step'\nset xtics 1\nset yrange [0:*]\n";
  const std::string each_server = "for [i=0:" + std::to_string(labels.size() - 1) + "] ";
  gp += gnuplot_png("servers_cpu.png",
                    "CPU of each server per step (100 % = one core): /metrics solid, /proc dashed",
                    "CPU %");
  gp += "plot " + each_server +
        "'servers.dat' index i u 1:3 w lp lw 2 lc i+1 t word(servers, i+1), " + each_server +
        "'' index i u 1:5 w lp dt 2 lc i+1 notitle" + kBaseline;
  gp += gnuplot_png("servers_rss.png", "RSS of each server per step, from /metrics", "MB");
  gp += "plot " + each_server +
        "'servers.dat' index i u 1:4 w lp lw 2 lc i+1 t word(servers, i+1)" + kBaseline;
  gp += gnuplot_png("servers_tick_p99.png", "tick p99 of each server's worst match per step", "ms");
  gp += "plot " + each_server +
        "'servers.dat' index i u 1:6 w lp lw 2 lc i+1 t word(servers, i+1), 4 w l lc rgb "
        "'red' dt 3 t '4 ms'\n";
  gp += "set xlabel 'generator'\nset style fill solid 0.6\nset boxwidth 0.25\n";
  gp += gnuplot_png("generators.png", "each generator's last step: bots and its own CPU", "bots");
  gp +=
      "set yrange [0:*]\nset y2range [0:*]\nset y2label 'CPU %'\nset y2tics\nplot "
      "'generators.dat' u ($1-0.27):2 w boxes t 'bots', '' u 1:3 w boxes t 'connected', '' u "
      "($1+0.27):4 axes x1y2 w boxes t 'CPU %'\nunset y2tics\nunset y2label\n";
  gp += gnuplot_png("rtt.png", "RTT over every generator's bots (last step, pooled samples)",
                    "fraction of samples");
  gp += "set xlabel 'ms'\nplot 'rtt.dat' u 1:2 w steps lw 2 notitle\n";
  gp += gnuplot_png("connect_ms.png", "connect time over every generator's bots (last step)",
                    "fraction of bots");
  gp += "plot 'connect.dat' u 1:2 w steps lw 2 notitle\n";
  gp += gnuplot_png("errors.png", "errors by kind, every generator (last step)", "count");
  gp +=
      "set xlabel ''\nset boxwidth 0.6\nset xtics rotate by -30\n"
      "plot 'errors.dat' u 0:2:xtic(1) w boxes notitle\nunset output\n";
  return run_gnuplot(dir, gp);
}

}  // namespace ricochet::loadtest
