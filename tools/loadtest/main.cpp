// ricochet-loadtest: many bots on one event loop against a ricochet-server on this host. Ramps
// up at a set rate, shows progress on stderr, reads the server's /metrics and /proc while it
// runs, and writes DIR/report.json, the series and gnuplot PNGs (one step, or --sweep steps).
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <filesystem>

#include "ricochet/loadtest/load_run.h"
#include "ricochet/loadtest/report.h"

namespace {

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace ricochet::loadtest;
  LoadTestConfig config;
  std::string duration = "60s";
  std::string settle = "5s";
  std::string sweep;
  std::string log_level = "off";
  bool predict = false;
  bool socket_per_bot = false;
  bool no_plots = false;
  bool quiet = false;

  CLI::App app{"ricochet-loadtest: bots against a ricochet-server on this host, measured"};
  app.add_option("--server", config.server, "the server's loopback IPv4 address")
      ->capture_default_str();
  app.add_option("--port", config.control_port, "control channel (TLS) port")
      ->capture_default_str();
  app.add_option("--admin-port", config.admin_port, "admin HTTP port (/metrics)")
      ->capture_default_str();
  app.add_option("--fingerprint", config.fingerprint,
                 "pin the server certificate's SHA-256 fingerprint (AA:BB:...)");
  app.add_option("--trust-file", config.trust_file,
                 "trust on first use into this file (default: DIR/server.fp)");
  app.add_option("--bots", config.bots, "bots (one step)")->capture_default_str();
  app.add_option("--sweep", sweep, "steps of increasing bot counts, e.g. 100,200,400");
  app.add_option("--match-size", config.match_size,
                 "players per match the server hosts (start it with --match-max-players)")
      ->capture_default_str();
  app.add_option("--duration", duration, "measured time per step (60s, 2m, 500ms)")
      ->capture_default_str();
  app.add_option("--ramp", config.ramp_per_s, "bots started per second")->capture_default_str();
  app.add_option("--settle", settle, "wait after the last start before measuring")
      ->capture_default_str();
  app.add_option("--bots-per-address", config.bots_per_address,
                 "bots per loopback source address (127.0.1.1, 127.0.1.2, ...)")
      ->capture_default_str();
  app.add_flag("--socket-per-bot", socket_per_bot,
               "a UDP socket per bot's game channel (default: one socket for all, a loopback "
               "source address per bot and batched system calls)");
  app.add_flag("--predict", predict,
               "full bots with prediction and interpolation (default: cheap bots, which send "
               "the same inputs at less CPU)");
  app.add_option("--skill", config.skill, "aim skill 0..1")->capture_default_str();
  app.add_option("--name", config.name, "account prefix (<name>s<step>-<k>)")
      ->capture_default_str();
  app.add_option("--password", config.password, "the bots' password")->capture_default_str();
  app.add_option("--scrape-interval", config.scrape_interval_s, "s between scrapes")
      ->capture_default_str();
  app.add_option("--server-pid", config.server_pid,
                 "the server's pid for /proc (0: from ricochet_process_id in /metrics)")
      ->capture_default_str();
  app.add_option("--out", config.out, "directory for report.json, the series and the PNGs")
      ->capture_default_str();
  app.add_flag("--no-plots", no_plots, "skip gnuplot");
  app.add_flag("--quiet", quiet, "no progress line per scrape");
  app.add_option("--log-level", log_level, "the bots' log: trace|debug|info|warn|error|off")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  const auto fail = [](const std::string& problem) {
    std::fprintf(stderr, "ricochet-loadtest: %s\n", problem.c_str());
    return 2;
  };
  const auto duration_s = parse_duration_s(duration);
  if (!duration_s)
    return fail("--duration must be a duration like 60s, 2m or 500ms, got \"" + duration + "\"");
  config.duration_s = *duration_s;
  const auto settle_s = parse_duration_s(settle);
  if (!settle_s) return fail("--settle must be a duration like 5s, got \"" + settle + "\"");
  config.settle_s = *settle_s;
  if (!sweep.empty()) {
    const auto counts = parse_bot_counts(sweep);
    if (!counts) {
      return fail("--sweep must be increasing positive bot counts separated by commas, got \"" +
                  sweep + "\"");
    }
    config.sweep = *counts;
  }
  config.cheap = !predict;
  config.shared_game_port = !socket_per_bot;
  config.plots = !no_plots;
  config.progress = !quiet;
  if (config.fingerprint.empty() && config.trust_file.empty()) {
    config.trust_file = (std::filesystem::path(config.out) / "server.fp").string();
  }
  if (const std::string problem = config.validate(); !problem.empty()) return fail(problem);
  std::error_code made;
  std::filesystem::create_directories(config.out, made);
  if (made) return fail("cannot create " + config.out + ": " + made.message());

  spdlog::set_default_logger(spdlog::stderr_color_mt("ricochet-loadtest"));
  spdlog::set_level(spdlog::level::from_str(log_level));

  ReportContext context;
  for (int i = 0; i < argc; ++i) {
    if (i > 0) context.command += ' ';
    context.command += argv[i];
  }
  context.measured_at_utc = utc_now();

  boost::asio::io_context io;
  LoadRun run(io, config);
  boost::asio::signal_set signals(io, SIGINT, SIGTERM);
  boost::asio::steady_timer linger(io);
  signals.async_wait([&](const boost::system::error_code& error, int signal) {
    if (!error) run.stop(signal == SIGINT ? "SIGINT" : "SIGTERM");
  });
  run.on_finished([&] {
    signals.cancel();
    // The bots' disconnect packets go out; then whatever is left is not waited for.
    linger.expires_after(std::chrono::seconds(2));
    linger.async_wait([&](const boost::system::error_code&) { io.stop(); });
  });
  run.start();
  io.run();

  int status = 0;
  if (const std::string problem = write_report(run, config, context); !problem.empty()) {
    std::fprintf(stderr, "ricochet-loadtest: %s\n", problem.c_str());
    status = 1;
  } else if (config.plots) {
    if (const std::string problem = draw_plots(run, config); !problem.empty()) {
      std::fprintf(stderr, "ricochet-loadtest: %s\n", problem.c_str());
      status = 1;
    }
  }
  std::fprintf(stderr, "ricochet-loadtest: wrote %s/report.json\n", config.out.c_str());
  return status;
}
