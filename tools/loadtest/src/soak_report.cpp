#include "ricochet/loadtest/soak_report.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "ricochet/tools/json_text.h"

namespace ricochet::loadtest {

namespace fs = std::filesystem;

namespace {

using tools::json_string;

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

std::string number(const std::optional<double>& value) {
  return value ? number(*value) : "null";
}

std::string field(const char* key, const std::string& value) {
  return std::string(",\"") + key + "\":" + value;
}

bool write_file(const fs::path& path, const std::string& text, std::string& error) {
  std::ofstream file(path);
  file << text;
  if (!file) {
    error = "cannot write " + path.string();
    return false;
  }
  return true;
}

std::string errors_json(const ErrorCounts& errors) {
  std::string out = "{";
  for (const auto& [kind, n] : errors) {
    if (n == 0) continue;
    if (out.size() > 1) out += ',';
    out += json_string(kind) + ':' + std::to_string(n);
  }
  return out + "}";
}

std::string report_json(const SoakRun& run, const SoakSummary& s, const LoadTestConfig& config,
                        const SoakConfig& soak, const ReportContext& context) {
  const Flatness& flat = s.flatness;
  std::string out = "{\"tool\":\"ricochet-loadtest\",\"mode\":\"soak\"";
  out += field("measured_at_utc", json_string(context.measured_at_utc));
  out += field("command", json_string(context.command));
  out += field("stop_reason", json_string(run.stop_reason()));
  out += field("completed", run.stop_reason() == "duration reached" ? "true" : "false");
  out += field("bots", std::to_string(config.bots));
  out += field("match_size", std::to_string(config.match_size));
  out += field("bots_per_address", std::to_string(config.bots_per_address));
  out += field("scrape_interval_s", number(config.scrape_interval_s));
  out += field("link", "{\"latency_ms\":" + number(soak.link.latency_ms) + ",\"jitter_ms\":" +
                           number(soak.link.jitter_ms) + ",\"loss\":" + number(soak.link.loss) +
                           ",\"duplicate\":" + number(soak.link.duplicate) + ",\"reorder\":" +
                           number(soak.link.reorder) + ",\"each_direction\":true}");
  out += field("churn", "{\"min_life_s\":" + number(soak.churn.min_life_s) +
                            ",\"max_life_s\":" + number(soak.churn.max_life_s) +
                            ",\"new_account_share\":" + number(soak.churn.new_account_share) + "}");
  out += field("duration_s", number(s.duration_s));
  out += field("warmup_s", number(flat.warmup_s));
  out += field("samples", std::to_string(s.samples));
  out += field("samples_after_warmup", std::to_string(flat.samples));
  out += field("flat", flat.flat() ? "true" : "false");
  out += field("verdict", json_string(flat.verdict()));
  out += field("rss_slope_mib_per_hour", number(flat.rss_mib_per_hour));
  out += field("rss_bound_mib_per_hour", number(flat.bounds.rss_mib_per_hour));
  out += field("fds_slope_per_hour", number(flat.fds_per_hour));
  out += field("fds_bound_per_hour", number(flat.bounds.fds_per_hour));
  out += field("rss_mib_first", number(s.rss_mib_first));
  out += field("rss_mib_last", number(s.rss_mib_last));
  out += field("rss_mib_max", number(s.rss_mib_max));
  out += field("fds_first", number(s.fds_first));
  out += field("fds_last", number(s.fds_last));
  out += field("fds_max", number(s.fds_max));
  out += field("db_mib_first", number(s.db_mib_first));
  out += field("db_mib_last", number(s.db_mib_last));
  out += field("db_mib_per_hour", number(s.db_mib_per_hour));
  out += field("tick_p99_ms_median", number(s.tick_p99_ms_median));
  out += field("tick_p99_ms_max", number(s.tick_p99_ms_max));
  out += field("tick_max_ms_max", number(s.tick_max_ms_max));
  out += field("snapshot_loss", number(s.snapshot_loss));
  out += field("packet_loss", number(s.packet_loss));
  out += field("playing_min", std::to_string(s.playing_min));
  out += field("playing_median", std::to_string(s.playing_median));
  out += field("sign_ins", std::to_string(s.sign_ins));
  out += field("new_accounts", std::to_string(s.new_accounts));
  out += field("departures", std::to_string(s.departures));
  out += field("matches_finished", std::to_string(s.matches_finished));
  out += field("scrapes_failed", std::to_string(s.scrapes_failed));
  out += field("errors_total", std::to_string(s.errors));
  out += field("errors", errors_json(run.errors()));
  out += field("bot_refusals", errors_json(run.refusals()));
  return out + "}";
}

std::string samples_table(const std::vector<SoakSample>& samples) {
  std::string out =
      "# t_s server_ok playing joining gave_up server_matches server_players tick_p99_ms "
      "tick_max_ms rss_mib open_fds db_mib loss_pct server_cpu_pct gen_cpu_pct sign_ins "
      "new_accounts departures matches_finished errors\n";
  char line[384];
  for (const SoakSample& s : samples) {
    std::snprintf(line, sizeof line,
                  "%.2f %d %d %d %d %d %d %.4f %.4f %.3f %.0f %.4f %.3f %.2f %.2f %llu %llu %llu "
                  "%llu %llu\n",
                  s.t_s, s.server_ok ? 1 : 0, s.playing, s.joining, s.gave_up, s.server_matches,
                  s.server_players, s.tick_p99_ms, s.tick_max_ms, s.rss_mib, s.open_fds, s.db_mib,
                  s.snapshot_loss * 100, s.server_cpu_percent, s.generator_cpu_percent,
                  static_cast<unsigned long long>(s.sign_ins),
                  static_cast<unsigned long long>(s.new_accounts),
                  static_cast<unsigned long long>(s.departures),
                  static_cast<unsigned long long>(s.matches_finished),
                  static_cast<unsigned long long>(s.errors));
    out += line;
  }
  return out;
}

std::string errors_table(const ErrorCounts& errors) {
  std::string out = "# kind count\n";
  bool any = false;
  for (const auto& [kind, n] : errors) {
    if (n == 0) continue;
    out += kind + ' ' + std::to_string(n) + '\n';
    any = true;
  }
  if (!any) out += "none 0\n";
  return out;
}

}  // namespace

std::string write_soak_report(const SoakRun& run, const SoakSummary& summary,
                              const LoadTestConfig& config, const SoakConfig& soak,
                              const ReportContext& context) {
  const fs::path dir(config.out);
  std::error_code made;
  fs::create_directories(dir, made);
  if (made) return "cannot create " + dir.string() + ": " + made.message();
  std::string error;
  if (!write_file(dir / "report.json", report_json(run, summary, config, soak, context) + "\n",
                  error) ||
      !write_file(dir / "soak.dat", samples_table(run.samples()), error) ||
      !write_file(dir / "errors.dat", errors_table(run.errors()), error)) {
    return error;
  }
  return {};
}

std::string draw_soak_plots(const SoakSummary& summary, const LoadTestConfig& config) {
  const fs::path dir(config.out);
  const std::string warmup = number(summary.flatness.warmup_s);
  std::string gp =
      "set terminal pngcairo size 960,600 noenhanced font 'sans,10'\n"
      "set grid\nset key top left\nset xlabel 'time since start (s)'\n"
      "set fit quiet logfile 'fit.log'\n"
      // The warm-up, left out of the slopes, shaded.
      "set object 1 rect from graph 0, graph 0 to first " +
      warmup + ", graph 1 fc rgb '#eeeeee' behind\n";
  const auto png = [&gp](const char* file, const char* title, const char* ylabel) {
    gp += std::string("set output '") + file + "'\nset title '" + title + "'\nset ylabel '" +
          ylabel + "'\n";
  };
  // Lines fitted over the samples after the warm-up (the slopes of report.json), when there are
  // enough of them; the columns are soak.dat's.
  const bool fitted = summary.flatness.rss_mib_per_hour && summary.flatness.fds_per_hour;
  if (fitted) {
    gp +=
        "r(x) = ra + rb * x\nf(x) = fa + fb * x\n"
        "fit [" +
        warmup +
        ":*] r(x) 'soak.dat' u 1:($10 >= 0 ? $10 : 1/0) via ra, rb\n"
        "fit [" +
        warmup + ":*] f(x) 'soak.dat' u 1:($11 >= 0 ? $11 : 1/0) via fa, fb\n";
  }
  png("rss_fds.png", "server RSS and open file descriptors (grey: warm-up)", "RSS (MiB)");
  gp +=
      "set y2label 'open fds'\nset y2tics\nplot 'soak.dat' u 1:($10 >= 0 ? $10 : 1/0) w l lw 2 "
      "t 'RSS MiB', '' u 1:($11 >= 0 ? $11 : 1/0) w l axes x1y2 t 'open fds'";
  if (fitted) {
    gp += ", [" + warmup + ":*] r(x) w l dt 2 lc rgb 'black' t 'RSS fit', [" + warmup +
          ":*] f(x) axes x1y2 w l dt 3 lc rgb 'black' t 'fds fit'";
  }
  gp += "\nunset y2tics\nunset y2label\n";
  png("db.png", "database file and WAL", "MiB");
  gp += "plot 'soak.dat' u 1:($12 >= 0 ? $12 : 1/0) w l lw 2 t 'db + wal MiB'\n";
  png("tick_p99.png", "server tick time, worst match (last 600 ticks)", "ms");
  gp +=
      "plot 'soak.dat' u 1:($2 > 0 ? $8 : 1/0) w l lw 2 t 'p99', '' u 1:($2 > 0 ? $9 : 1/0) w "
      "l t 'max', 4 w l lc rgb 'red' dt 3 t '4 ms'\n";
  png("snapshot_loss.png", "snapshot loss seen by bots (each scrape interval)", "%");
  gp += "plot 'soak.dat' u 1:13 w l t 'loss %'\n";
  png("bots.png", "bots and what they did", "bots");
  gp +=
      "set y2label 'since start'\nset y2tics\nplot 'soak.dat' u 1:3 w l lw 2 t 'playing', '' u "
      "1:4 w l t 'joining', '' u 1:5 w l t 'gave up', '' u 1:16 w l axes x1y2 t 'sign-ins', '' "
      "u 1:18 w l axes x1y2 t 'left', '' u 1:19 w l axes x1y2 t 'matches finished', '' u 1:20 "
      "w l axes x1y2 t 'errors'\nunset y2tics\nunset y2label\n";
  png("cpu.png", "CPU (100 % = one core), from /proc", "CPU %");
  gp += "plot 'soak.dat' u 1:14 w l lw 2 t 'server', '' u 1:15 w l t 'generator'\n";
  png("errors.png", "errors by kind (whole run)", "count");
  gp +=
      "unset object 1\nset xlabel ''\nset style fill solid 0.6\nset boxwidth 0.6\n"
      "set xtics rotate by -30\nplot 'errors.dat' u 0:2:xtic(1) w boxes notitle\n";
  gp += "unset output\n";
  std::string error;
  if (!write_file(dir / "plots.gp", gp, error)) return error;
  if (dir.string().find('\'') != std::string::npos) return "the out directory's name has a quote";
  const std::string command = "cd '" + dir.string() + "' && gnuplot plots.gp > gnuplot.log 2>&1";
  const int status = std::system(command.c_str());
  if (status != 0) {
    return "gnuplot failed (status " + std::to_string(status) + "; see " +
           (dir / "gnuplot.log").string() + "; tools/deps.sh installs gnuplot-nox)";
  }
  return {};
}

}  // namespace ricochet::loadtest
