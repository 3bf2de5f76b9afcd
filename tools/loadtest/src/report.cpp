#include "ricochet/loadtest/report.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

#include "report_files.h"
#include "ricochet/loadtest/capacity.h"
#include "ricochet/tools/json_text.h"

namespace ricochet::loadtest {

namespace fs = std::filesystem;

namespace {

using tools::json_string;

std::string report_json(const LoadRun& run, const LoadTestConfig& config,
                        const ReportContext& context) {
  const std::vector<StepSummary>& steps = run.steps();
  std::string out = "{\"tool\":\"ricochet-loadtest\",\"measured_at_utc\":" +
                    json_string(context.measured_at_utc) +
                    ",\"command\":" + json_string(context.command) +
                    ",\"stop_reason\":" + json_string(run.stop_reason()) +
                    ",\"match_size\":" + std::to_string(config.match_size) +
                    ",\"cheap\":" + (config.cheap ? "true" : "false") +
                    ",\"shared_game_port\":" + (config.shared_game_port ? "true" : "false") +
                    ",\"ramp_per_s\":" + std::to_string(config.ramp_per_s) +
                    ",\"bots_per_address\":" + std::to_string(config.bots_per_address) +
                    ",\"find_match\":" + json_string(config.find_match) +
                    ",\"capacity_bots\":" + std::to_string(capacity_bots(steps)) +
                    ",\"samples\":" + std::to_string(run.samples().size()) + ",\"steps\":[";
  for (std::size_t i = 0; i < steps.size(); ++i) {
    if (i > 0) out += ',';
    out += steps[i].to_json(/*samples=*/true);
  }
  out += "],";
  // The last step's figures at the top level (the whole report of a run without --sweep).
  const StepSummary last = steps.empty() ? StepSummary{} : steps.back();
  std::string last_json = last.to_json();
  if (steps.empty()) {
    StepSummary empty;
    empty.errors = run.errors();
    last_json = empty.to_json();
  }
  out += last_json.substr(1);  // without its '{'
  return out;
}

/// One JSON line per step, each with when and how it was measured (for results/*.jsonl).
std::string steps_lines(const LoadRun& run, const LoadTestConfig& config,
                        const ReportContext& context) {
  std::string out;
  for (const StepSummary& step : run.steps()) {
    out += "{\"bench\":\"capacity\",\"measured_at_utc\":" + json_string(context.measured_at_utc) +
           ",\"command\":" + json_string(context.command) +
           ",\"match_size\":" + std::to_string(config.match_size) +
           ",\"cheap\":" + (config.cheap ? "true" : "false") + ',' + step.to_json().substr(1) +
           '\n';
  }
  return out;
}

std::string samples_table(const std::vector<RunSample>& samples) {
  std::string out =
      "# t_s step_bots measuring playing joining gave_up matches tick_p50 tick_p95 tick_p99 "
      "tick_max tick_p99_mean overruns dropped_steps server_cpu_pct server_rss_mb gen_cpu_pct "
      "gen_rss_mb kbps_in kbps_out rtt_p50 rtt_p99 loss_pct errors pps_in pps_out\n";
  char line[512];
  for (const RunSample& s : samples) {
    std::snprintf(line, sizeof line,
                  "%.2f %d %d %d %d %d %d %.4f %.4f %.4f %.4f %.4f %.0f %.0f %.2f %.2f %.2f %.2f "
                  "%.2f %.2f %.3f %.3f %.4f %llu %.1f %.1f\n",
                  s.t_s, s.step_bots, s.measuring ? 1 : 0, s.playing, s.joining, s.done, s.matches,
                  s.tick.p50_ms, s.tick.p95_ms, s.tick.p99_ms, s.tick.max_ms, s.tick_p99_mean_ms,
                  s.overruns, s.dropped_steps, s.server_cpu_percent, s.server_rss_mb,
                  s.generator_cpu_percent, s.generator_rss_mb, s.kbps_in_per_client,
                  s.kbps_out_per_client, s.rtt_ms_p50, s.rtt_ms_p99, s.snapshot_loss * 100,
                  static_cast<unsigned long long>(s.errors), s.server_packets_in_per_s,
                  s.server_packets_out_per_s);
    out += line;
  }
  return out;
}

/// One gnuplot data block per match of each server (separated by two blank lines: `index i`).
std::string matches_table(const std::vector<MatchTickRow>& rows, std::size_t& blocks) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<const MatchTickRow*>> by_match;
  for (const MatchTickRow& row : rows) by_match[{row.server, row.match}].push_back(&row);
  std::string out = "# per match: t_s match tick_p50 tick_p95 tick_p99 tick_max (ms) server\n";
  char line[160];
  for (const auto& [id, list] : by_match) {
    for (const MatchTickRow* row : list) {
      std::snprintf(line, sizeof line, "%.2f %u %.4f %.4f %.4f %.4f %u\n", row->t_s, id.second,
                    row->tick.p50_ms, row->tick.p95_ms, row->tick.p99_ms, row->tick.max_ms,
                    id.first);
      out += line;
    }
    out += "\n\n";
  }
  blocks = by_match.size();
  return out;
}

/// One gnuplot data block per server (`index i`, in the order of --server): its scrapes.
std::string servers_table(const std::vector<ServerTracker>& servers) {
  std::string out =
      "# per server: t_s ok cpu_pct rss_mb cpu_pct_proc rss_mb_proc tick_p99 tick_max matches "
      "players (-1: not known)\n";
  char line[256];
  for (const ServerTracker& server : servers) {
    out += "# " + server.label() + "\n";
    for (const ServerPoint& p : server.points()) {
      std::snprintf(line, sizeof line, "%.2f %d %.2f %.2f %.2f %.2f %.4f %.4f %d %d\n", p.t_s,
                    p.ok ? 1 : 0, p.cpu_percent, p.rss_mb, p.cpu_percent_proc, p.rss_mb_proc,
                    p.tick.p99_ms, p.tick.max_ms, p.matches, p.players);
      out += line;
    }
    out += "\n\n";
  }
  return out;
}

std::string sweep_table(const std::vector<StepSummary>& steps) {
  std::string out =
      "# bots bots_connected tick_p99 tick_max server_cpu_pct gen_cpu_pct kbps_in kbps_out "
      "loss_pct rtt_p99 overruns\n";
  char line[256];
  for (const StepSummary& s : steps) {
    std::snprintf(line, sizeof line, "%d %d %.4f %.4f %.2f %.2f %.2f %.2f %.4f %.3f %.0f\n", s.bots,
                  s.bots_connected, s.server_tick.p99_ms, s.server_tick.max_ms,
                  s.server_cpu_percent, s.generator_cpu_percent, s.kbps_in_per_client,
                  s.kbps_out_per_client, s.snapshot_loss * 100, s.rtt_ms_p99, s.overruns);
    out += line;
  }
  return out;
}

ErrorCounts final_errors(const LoadRun& run) {
  if (!run.steps().empty()) return run.steps().back().errors;
  return run.errors();
}

}  // namespace

std::string write_report(const LoadRun& run, const LoadTestConfig& config,
                         const ReportContext& context) {
  const fs::path dir(config.out);
  std::error_code made;
  fs::create_directories(dir, made);
  if (made) return "cannot create " + dir.string() + ": " + made.message();
  std::string error;
  std::size_t blocks = 0;
  if (!write_file(dir / "report.json", report_json(run, config, context) + "\n", error) ||
      !write_file(dir / "samples.dat", samples_table(run.samples()), error) ||
      !write_file(dir / "matches.dat", matches_table(run.match_rows(), blocks), error) ||
      !write_file(dir / "servers.dat", servers_table(run.servers()), error) ||
      !write_file(dir / "errors.dat", errors_table(final_errors(run)), error) ||
      !write_file(dir / "connect.dat",
                  distribution_table(run.connect_ms(), "# connect_ms fraction_of_bots"), error) ||
      !write_file(dir / "sweep.dat", sweep_table(run.steps()), error) ||
      !write_file(dir / "steps.jsonl", steps_lines(run, config, context), error)) {
    return error;
  }
  return {};
}

std::string draw_plots(const LoadRun& run, const LoadTestConfig& config) {
  const fs::path dir(config.out);
  std::set<std::pair<std::uint32_t, std::uint32_t>> ids;
  for (const MatchTickRow& row : run.match_rows()) ids.insert({row.server, row.match});
  std::string gp = std::string(kGnuplotPreamble);
  const auto png = [&gp](const char* file, const char* title, const char* ylabel) {
    gp += gnuplot_png(file, title, ylabel);
  };
  png("tick_ms.png", "server tick time, worst match (last 600 ticks)", "ms");
  gp +=
      "plot 'samples.dat' u 1:8 w l t 'p50', '' u 1:9 w l t 'p95', '' u 1:10 w l lw 2 t "
      "'p99', '' u 1:11 w l t 'max', '' u 1:12 w l dt 2 t 'p99 mean of matches', 4 w l lc "
      "rgb 'red' dt 3 t '4 ms'\n";
  png("tick_p99_per_match.png", "server tick p99 per match (last 600 ticks)", "ms");
  if (ids.empty()) {
    gp += "plot 0 notitle\n";
  } else {
    gp += "plot for [i=0:" + std::to_string(ids.size() - 1) +
          "] 'matches.dat' index i u 1:5 w l notitle, 4 w l lc rgb 'red' dt 3 t '4 ms'\n";
  }
  png("overruns.png", "server tick overruns and dropped steps (since start)", "ticks");
  gp += "plot 'samples.dat' u 1:13 w l lw 2 t 'overruns', '' u 1:14 w l t 'dropped steps'\n";
  png("cpu_rss.png",
      "CPU (100 % = one core) and RSS: the busiest server from its /metrics, the generator from "
      "/proc",
      "CPU %");
  gp +=
      "set y2label 'RSS (MB)'\nset y2tics\nplot 'samples.dat' u 1:15 w l lw 2 t 'server CPU "
      "%', '' u 1:17 w l t 'generator CPU %', '' u 1:16 w l axes x1y2 t 'server RSS MB', '' "
      "u 1:18 w l axes x1y2 t 'generator RSS MB'\nunset y2tics\nunset y2label\n";
  // Each server: CPU from its /metrics (solid) and from /proc where read (dashed), and RSS; a
  // zero line over the scrapes' times, so that a plot whose every value is missing is drawn.
  const std::string baseline = ", 'servers.dat' index 0 u 1:(0) w l lc rgb 'gray' notitle\n";
  const std::size_t servers = run.servers().size();
  std::string titles;
  for (std::size_t i = 0; i < servers; ++i) {
    titles += (i ? " " : "") + run.servers()[i].label();
  }
  gp += "servers = '" + titles + "'\nset datafile missing '-1.00'\n";
  png("servers_cpu.png", "CPU of each server (100 % = one core): /metrics solid, /proc dashed",
      "CPU %");
  gp += "plot for [i=0:" + std::to_string(servers - 1) +
        "] 'servers.dat' index i u 1:3 w l lw 2 lc i+1 t word(servers, i+1), for [i=0:" +
        std::to_string(servers - 1) + "] '' index i u 1:5 w l dt 2 lc i+1 notitle" + baseline;
  png("servers_rss.png", "RSS of each server: /metrics solid, /proc dashed", "MB");
  gp += "plot for [i=0:" + std::to_string(servers - 1) +
        "] 'servers.dat' index i u 1:4 w l lw 2 lc i+1 t word(servers, i+1), for [i=0:" +
        std::to_string(servers - 1) + "] '' index i u 1:6 w l dt 2 lc i+1 notitle" + baseline;
  png("bandwidth.png", "game bandwidth per client, as bots see it", "kbit/s");
  gp +=
      "plot 'samples.dat' u 1:19 w l t 'in (server to bot)', '' u 1:20 w l t 'out (bot to "
      "server)'\n";
  png("rtt_loss.png", "RTT and snapshot loss seen by bots", "RTT (ms)");
  gp +=
      "set y2label 'snapshot loss (%)'\nset y2tics\nplot 'samples.dat' u 1:21 w l t 'RTT "
      "p50', '' u 1:22 w l t 'RTT p99', '' u 1:23 w l axes x1y2 t 'loss %'\nunset "
      "y2tics\nunset y2label\n";
  png("bots.png", "bots by state", "bots");
  gp +=
      "plot 'samples.dat' u 1:4 w l lw 2 t 'playing', '' u 1:5 w l t 'joining', '' u 1:6 w l "
      "t 'gave up', '' u 1:2 w l dt 2 t 'target'\n";
  png("errors.png", "errors by kind (whole run)", "count");
  gp +=
      "set xlabel ''\nset style fill solid 0.6\nset boxwidth 0.6\nset xtics rotate by -30\n"
      "plot 'errors.dat' u 0:2:xtic(1) w boxes notitle\nset xtics norotate\n";
  png("connect_ms.png", "connect time: bot start to first snapshot (sign-in included)",
      "fraction of bots");
  gp += "set xlabel 'ms'\nplot 'connect.dat' u 1:2 w steps lw 2 notitle\n";
  if (run.steps().size() > 1) {
    gp += "set xlabel 'bots'\n";
    png("sweep_tick_p99.png", "sweep: server tick p99 (worst match) against bots", "ms");
    gp +=
        "plot 'sweep.dat' u 1:3 w lp lw 2 t 'p99', '' u 1:4 w lp t 'max', 4 w l lc rgb 'red' "
        "dt 3 t '4 ms'\n";
    png("sweep_cpu.png", "sweep: CPU against bots (100 % = one core)", "CPU %");
    gp += "plot 'sweep.dat' u 1:5 w lp lw 2 t 'server', '' u 1:6 w lp t 'generator'\n";
    png("sweep_kbps.png", "sweep: bandwidth per client against bots", "kbit/s");
    gp += "plot 'sweep.dat' u 1:7 w lp lw 2 t 'in (server to bot)', '' u 1:8 w lp t 'out'\n";
  }
  gp += "unset output\n";
  return run_gnuplot(dir, gp);
}

}  // namespace ricochet::loadtest
