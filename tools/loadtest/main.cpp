// ricochet-loadtest: many bots on one event loop against one or several ricochet-servers. Ramps
// up at a set rate, shows progress on stderr, reads every server's /metrics (and /proc, on this
// host, for the comparison) while it runs, and writes DIR/report.json, the series and gnuplot
// PNGs (one step, or --sweep steps).
// With --soak: bots on a bad link coming and going for the whole duration, and whether the
// server's RSS and open descriptors stayed flat (soak_run.h).
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
#include <variant>

#include "ricochet/loadtest/admin_token.h"
#include "ricochet/loadtest/fleet_directory.h"
#include "ricochet/loadtest/load_run.h"
#include "ricochet/loadtest/merge.h"
#include "ricochet/loadtest/metrics_client.h"
#include "ricochet/loadtest/report.h"
#include "ricochet/loadtest/soak_report.h"
#include "ricochet/loadtest/soak_run.h"

namespace {

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

/// Exit codes (--help lists them).
constexpr int kExitReportFailed = 1;
constexpr int kExitBadOption = 2;
constexpr int kExitNotFlat = 3;

/// The servers `source`'s GET /fleet lists (fleet_directory.h), or why not. Waits at most 10 s.
std::variant<std::vector<ricochet::loadtest::ServerEndpoint>, std::string> discover_fleet(
    const ricochet::loadtest::ServerEndpoint& source) {
  using namespace ricochet::loadtest;
  boost::asio::io_context io;
  MetricsResponse answer;
  fetch_admin(
      io,
      boost::asio::ip::tcp::endpoint(boost::asio::ip::make_address(source.host), source.admin_port),
      "/fleet", kMaxFleetBytes, source.admin_token, 10,
      [&answer](MetricsResponse response) { answer = std::move(response); });
  io.run();
  if (!answer.error.empty()) {
    return answer.error + (answer.status == 401 ? " (give its admin token with --admin-token-file)"
                           : answer.status == 404
                               ? " (a server keeps the directory with [placement] on)"
                               : "");
  }
  FleetReader reader;
  auto read = reader.read(answer.body);
  if (const auto* refused = std::get_if<FleetError>(&read)) {
    return std::string("refused its answer (") + name(refused->reason) + "): " + refused->message;
  }
  return std::get<std::vector<ServerEndpoint>>(std::move(read));
}

/// Runs `run` on `io` until it finishes (SIGINT/SIGTERM end it early), then lets the bots'
/// disconnect packets out.
template <class Run>
void run_to_the_end(boost::asio::io_context& io, Run& run) {
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
}

int soak(const ricochet::loadtest::LoadTestConfig& config,
         const ricochet::loadtest::SoakConfig& options,
         const ricochet::loadtest::ReportContext& context) {
  using namespace ricochet::loadtest;
  boost::asio::io_context io;
  SoakRun run(io, config, options);
  run_to_the_end(io, run);
  const SoakSummary summary =
      summarise_soak(run.samples(), options.warmup_for(config.duration_s), options.bounds);
  if (const std::string problem = write_soak_report(run, summary, config, options, context);
      !problem.empty()) {
    std::fprintf(stderr, "ricochet-loadtest: %s\n", problem.c_str());
    return kExitReportFailed;
  }
  int status = 0;
  if (config.plots) {
    if (const std::string problem = draw_soak_plots(summary, config); !problem.empty()) {
      std::fprintf(stderr, "ricochet-loadtest: %s\n", problem.c_str());
      status = kExitReportFailed;
    }
  }
  const Flatness& flat = summary.flatness;
  std::fprintf(stderr,
               "ricochet-loadtest: soak %s: RSS %+.2f MiB/h (bound %.2f), open fds %+.2f /h "
               "(bound %.2f) over %d samples after %.0f s of warm-up; wrote %s/report.json\n",
               flat.flat() ? "flat" : "NOT FLAT", flat.rss_mib_per_hour.value_or(0),
               flat.bounds.rss_mib_per_hour, flat.fds_per_hour.value_or(0),
               flat.bounds.fds_per_hour, flat.samples, flat.warmup_s, config.out.c_str());
  if (!flat.flat()) {
    std::fprintf(stderr, "ricochet-loadtest: %s\n", flat.verdict().c_str());
    return kExitNotFlat;
  }
  return status;
}

/// `ricochet-loadtest merge [--skip-bad] [--no-plots] OUT DIR...` (merge.h).
int merge(int argc, char** argv) {
  using namespace ricochet::loadtest;
  std::string out;
  std::vector<std::string> dirs;
  bool skip_bad = false;
  bool no_plots = false;
  CLI::App app{
      "ricochet-loadtest merge: the reports of generators run at the same time (one per "
      "machine, each with its own --name, against the same --server list) as one report in OUT.\n"
      "Exit status: 0 merged, 1 the report or its plots could not be written, 2 a bad option or "
      "a bad report (named)"};
  app.add_option("OUT", out, "directory for the merged report.json, data files and PNGs")
      ->required();
  app.add_option("DIR", dirs, "each generator's --out directory (its report.json)")->required();
  app.add_flag("--skip-bad", skip_bad,
               "leave out a missing, truncated or malformed report (named in report.json's "
               "\"skipped\") instead of refusing the merge");
  app.add_flag("--no-plots", no_plots, "skip gnuplot");
  CLI11_PARSE(app, argc, argv);
  auto merged = merge_directories(dirs, skip_bad);
  if (const auto* problem = std::get_if<std::string>(&merged)) {
    std::fprintf(stderr, "ricochet-loadtest merge: %s\n", problem->c_str());
    return kExitBadOption;
  }
  ReportContext context;
  context.command = "ricochet-loadtest merge";
  for (int i = 1; i < argc; ++i) context.command += std::string(" ") + argv[i];
  context.measured_at_utc = utc_now();
  const MergedReport& report = std::get<MergedReport>(merged);
  if (const std::string problem = write_merged_report(report, out, !no_plots, context);
      !problem.empty()) {
    std::fprintf(stderr, "ricochet-loadtest merge: %s\n", problem.c_str());
    return kExitReportFailed;
  }
  const StepSummary& last = report.steps.back();
  std::fprintf(stderr,
               "ricochet-loadtest merge: %zu generators (%zu skipped), %zu steps; last: %d of %d "
               "bots connected over %zu servers; wrote %s/report.json\n",
               report.generators.size(), report.skipped.size(), report.steps.size(),
               last.bots_connected, last.bots, last.servers.size(), out.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace ricochet::loadtest;
  if (argc >= 2 && std::string_view(argv[1]) == "merge") return merge(argc - 1, argv + 1);
  LoadTestConfig config;
  std::string duration = "60s";
  std::string settle = "5s";
  std::string sweep;
  std::string log_level = "off";
  bool predict = false;
  bool socket_per_bot = false;
  bool no_plots = false;
  bool quiet = false;
  bool soak_mode = false;
  SoakConfig soak_options;
  std::string link_latency = "200ms";
  std::string link_jitter = "50ms";
  std::string churn_min_life = "60s";
  std::string churn_max_life = "600s";
  std::string warmup;
  std::string server_proc = "auto";
  std::string servers = "127.0.0.1";
  std::uint16_t control_port = 7777;
  std::uint16_t admin_port = 9100;
  std::string fingerprints;
  std::string trust_file;
  std::string token_files;
  std::string fleet;

  CLI::App app{
      "ricochet-loadtest: bots against ricochet-servers, measured. `ricochet-loadtest merge "
      "--help`: the reports of several generators as one.\n"
      "Exit status: 0 the report is written (with --soak: and the server stayed flat), 1 the "
      "report or its plots could not be written, 2 a bad option, 3 (--soak) the server's RSS or "
      "open fds grew faster than their bounds after the warm-up"};
  auto* server_option =
      app.add_option("--server", servers,
                     "the servers, HOST[:CONTROL_PORT[:ADMIN_PORT]] separated by commas (numeric "
                     "IPv4; a port left out is --port's or --admin-port's); bots go round robin")
          ->capture_default_str();
  app.add_option(
      "--fleet", fleet,
      "HOST:ADMIN_PORT of one server: the servers are every row of its fleet directory (GET "
      "/fleet, read once at start, with --admin-token-file), that server first, each as if "
      "listed by --server with the certificate its row names; a row without an admin port is "
      "played on, its CPU unknown (metrics_not_advertised); not with --server or "
      "--fingerprint");
  app.add_option("--port", control_port, "control channel (TLS) port")->capture_default_str();
  app.add_option("--admin-port", admin_port, "admin HTTP port (/metrics)")->capture_default_str();
  app.add_option("--fingerprint", fingerprints,
                 "pin the servers' certificate SHA-256 fingerprints (AA:BB:...): one for every "
                 "server, or one per server separated by commas, in --server's order");
  app.add_option("--trust-file", trust_file,
                 "trust on first use into this file (default: DIR/server.fp; with several "
                 "servers FILE-2, FILE-3, ... for the others)");
  app.add_option("--find-match", config.find_match,
                 "MODE or MODE:MAP: every bot asks the first --server (or the --fleet server) "
                 "for a seat (find_match) and plays where the assignment sends it; the other "
                 "servers are scraped");
  app.add_option("--admin-token-file", token_files,
                 "the servers' admin bearer token (their --admin-token-file), sent on every "
                 "/metrics scrape: one file for every server, or one per server separated by "
                 "commas, in --server's order");
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
  auto* per_address =
      app.add_option("--bots-per-address", config.bots_per_address,
                     "bots per loopback source address (127.0.1.1, 127.0.1.2, ...); 2 with --soak")
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
  app.add_option("--server-proc", server_proc,
                 "the servers' CPU and RSS come from their /metrics; auto: read /proc as well (for "
                 "the comparison) when a server is on loopback and its pid's entry reads; off: "
                 "never")
      ->capture_default_str();
  app.add_option("--out", config.out, "directory for report.json, the series and the PNGs")
      ->capture_default_str();
  app.add_flag("--no-plots", no_plots, "skip gnuplot");
  app.add_flag("--quiet", quiet, "no progress line per scrape");
  app.add_option("--log-level", log_level, "the bots' log: trace|debug|info|warn|error|off")
      ->capture_default_str();
  app.add_flag("--soak", soak_mode,
               "soak: --bots stay for --duration through a bad link, leaving and coming back, "
               "and the server's RSS and open fds must stay flat after the warm-up (exit 3 if "
               "not); report.json, soak.dat and PNGs in DIR");
  app.add_option("--link-latency", link_latency, "soak: game channel latency, each way")
      ->capture_default_str();
  app.add_option("--link-jitter", link_jitter, "soak: ± uniform jitter on the latency, each way")
      ->capture_default_str();
  app.add_option("--link-loss", soak_options.link.loss, "soak: datagrams lost, each way (0..1)")
      ->capture_default_str();
  app.add_option("--link-duplicate", soak_options.link.duplicate,
                 "soak: datagrams delivered twice, each way (0..1)")
      ->capture_default_str();
  app.add_option("--link-reorder", soak_options.link.reorder,
                 "soak: datagrams held back so later ones overtake them, each way (0..1)")
      ->capture_default_str();
  app.add_option("--churn-min-life", churn_min_life,
                 "soak: shortest time a bot plays before it leaves and a new one takes its place")
      ->capture_default_str();
  app.add_option("--churn-max-life", churn_max_life, "soak: longest such time; 0: no churn")
      ->capture_default_str();
  app.add_option("--churn-new-account", soak_options.churn.new_account_share,
                 "soak: share of returning bots that sign in with a new account (0..1)")
      ->capture_default_str();
  app.add_option("--warmup", warmup,
                 "soak: time left out of the slopes (default: 10 % of --duration, at least 60s)");
  app.add_option("--max-rss-slope", soak_options.bounds.rss_mib_per_hour,
                 "soak: the largest flat RSS slope after the warm-up, MiB/hour")
      ->capture_default_str();
  app.add_option("--max-fd-slope", soak_options.bounds.fds_per_hour,
                 "soak: the largest flat open-fd slope after the warm-up, fds/hour")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  const auto fail = [](const std::string& problem) {
    std::fprintf(stderr, "ricochet-loadtest: %s\n", problem.c_str());
    return kExitBadOption;
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
  if (const auto mode = parse_server_proc(server_proc)) {
    config.server_proc = *mode;
  } else {
    return fail("--server-proc must be off or auto, got \"" + server_proc + "\"");
  }
  config.cheap = !predict;
  config.shared_game_port = !socket_per_bot;
  config.plots = !no_plots;
  config.progress = !quiet;
  const std::vector<std::string> token_paths = split_list(token_files);
  if (!fleet.empty() && (server_option->count() > 0 || !fingerprints.empty())) {
    return fail(
        "--fleet finds the servers and their certificates in the fleet directory: drop --server "
        "and --fingerprint, or --fleet");
  }
  if (!fleet.empty()) {
    auto source = parse_fleet_source(fleet);
    if (const auto* problem = std::get_if<std::string>(&source))
      return fail("--fleet: " + *problem);
    ServerEndpoint& asked = std::get<ServerEndpoint>(source);
    if (token_paths.size() > 1) return fail("--admin-token-file: one file with --fleet");
    if (!token_paths.empty()) {
      if (std::string problem = read_admin_token(token_paths[0], asked.admin_token);
          !problem.empty()) {
        return fail("--admin-token-file: " + problem);
      }
    }
    auto found = discover_fleet(asked);
    if (const auto* problem = std::get_if<std::string>(&found)) {
      return fail("--fleet " + fleet + ": " + *problem);
    }
    config.servers = std::get<std::vector<ServerEndpoint>>(std::move(found));
    std::string listed;
    for (const ServerEndpoint& server : config.servers) {
      listed += " " + server.label() +
                (server.admin_port != 0 ? " (admin " + std::to_string(server.admin_port) + ")"
                                        : " (no admin port)");
    }
    std::fprintf(stderr, "ricochet-loadtest: --fleet %s: %zu servers:%s\n", fleet.c_str(),
                 config.servers.size(), listed.c_str());
  } else {
    auto parsed = parse_servers(servers, control_port, admin_port);
    if (const auto* problem = std::get_if<std::string>(&parsed))
      return fail("--server: " + *problem);
    config.servers = std::get<std::vector<ServerEndpoint>>(std::move(parsed));
  }
  const std::vector<std::string> pins = split_list(fingerprints);
  if (pins.size() > 1 && pins.size() != config.servers.size()) {
    return fail("--fingerprint: one for every server or one per server (" +
                std::to_string(config.servers.size()) + "), got " + std::to_string(pins.size()));
  }
  if (token_paths.size() > 1 && token_paths.size() != config.servers.size()) {
    return fail("--admin-token-file: one for every server or one per server (" +
                std::to_string(config.servers.size()) + "), got " +
                std::to_string(token_paths.size()));
  }
  if (trust_file.empty()) trust_file = (std::filesystem::path(config.out) / "server.fp").string();
  for (std::size_t i = 0; i < config.servers.size(); ++i) {
    ServerEndpoint& server = config.servers[i];
    if (!pins.empty()) server.fingerprint = pins[pins.size() == 1 ? 0 : i];
    if (!token_paths.empty()) {
      const std::string& path = token_paths[token_paths.size() == 1 ? 0 : i];
      if (std::string problem = read_admin_token(path, server.admin_token); !problem.empty()) {
        return fail("--admin-token-file: " + problem);
      }
    }
    if (server.fingerprint.empty()) {
      server.trust_file = i == 0 ? trust_file : trust_file + "-" + std::to_string(i + 1);
    }
  }
  if (soak_mode && !config.find_match.empty()) {
    return fail(
        "--soak keeps its bots on one server's listed matches; --find-match is for load "
        "tests of placement (drop --soak or --find-match)");
  }
  if (soak_mode && per_address->count() == 0) config.bots_per_address = 2;
  if (const std::string problem = config.validate(); !problem.empty()) return fail(problem);
  if (soak_mode) {
    const auto latency_ms = parse_duration_s(link_latency);
    const auto jitter_ms = parse_duration_s(link_jitter);
    const auto min_life_s = parse_duration_s(churn_min_life);
    const auto max_life_s = parse_duration_s(churn_max_life);
    if (!latency_ms || !jitter_ms)
      return fail("--link-latency and --link-jitter must be durations like 200ms");
    if (!min_life_s || !max_life_s)
      return fail("--churn-min-life and --churn-max-life must be durations like 60s or 10m");
    soak_options.link.latency_ms = *latency_ms * 1000;
    soak_options.link.jitter_ms = *jitter_ms * 1000;
    soak_options.churn.min_life_s = *min_life_s;
    soak_options.churn.max_life_s = *max_life_s;
    if (!warmup.empty()) {
      const auto warmup_s = parse_duration_s(warmup);
      if (!warmup_s) return fail("--warmup must be a duration like 60s, got \"" + warmup + "\"");
      soak_options.warmup_s = *warmup_s;
    }
    if (const std::string problem = soak_options.validate(config); !problem.empty())
      return fail(problem);
  }
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

  if (soak_mode) return soak(config, soak_options, context);

  boost::asio::io_context io;
  LoadRun run(io, config);
  run_to_the_end(io, run);

  int status = 0;
  if (const std::string problem = write_report(run, config, context); !problem.empty()) {
    std::fprintf(stderr, "ricochet-loadtest: %s\n", problem.c_str());
    status = kExitReportFailed;
  } else if (config.plots) {
    if (const std::string problem = draw_plots(run, config); !problem.empty()) {
      std::fprintf(stderr, "ricochet-loadtest: %s\n", problem.c_str());
      status = kExitReportFailed;
    }
  }
  std::fprintf(stderr, "ricochet-loadtest: wrote %s/report.json\n", config.out.c_str());
  return status;
}
