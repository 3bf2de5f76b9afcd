// ricochet-bot: headless players over real sockets. Signs in over TLS (the server pinned by its
// certificate fingerprint, or trusted on first use), joins a match, plays over UDP, and prints
// what a player feels (RTT, snapshot rate and loss, bandwidth, time to first snapshot, kills) as
// one JSON line when it stops: at the end of --duration-s, of --matches, or on SIGINT/SIGTERM.
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>
#include <csignal>
#include <cstdio>
#include <iostream>

#include "ricochet/bot/fleet.h"

int main(int argc, char** argv) {
  using namespace ricochet::bot;
  FleetConfig config;
  BotConfig& bot = config.bot;
  double duration_s = 0;
  std::string log_level = "warn";
  int spacing_ms = static_cast<int>(config.start_spacing.count());

  CLI::App app{"ricochet-bot: headless Ricochet players for tests and load"};
  app.add_option("--host", bot.host, "server IP address")->capture_default_str();
  app.add_option("--port", bot.control_port, "control channel (TLS) port")->capture_default_str();
  app.add_option("--fingerprint", bot.fingerprint,
                 "pin the server certificate's SHA-256 fingerprint (AA:BB:...)");
  app.add_option("--trust-file", bot.trust_file,
                 "trust on first use: the fingerprint file, created on the first connection");
  app.add_option("--name", bot.name, "account name (with --bots N: <name>-1 .. <name>-N)")
      ->capture_default_str();
  app.add_option("--password", bot.password, "account password (registered if new)")
      ->capture_default_str();
  app.add_option("--match", bot.match_id, "match id to join; 0: the first with room")
      ->capture_default_str();
  app.add_option("--find-match", bot.find_match,
                 "MODE[:MAP]: ask the server for a seat (find_match) and follow the assignment, "
                 "to another server of its fleet if need be; after each match, ask it again");
  app.add_option("--skill", bot.skill, "aim skill 0..1 (1: no aim error)")->capture_default_str();
  app.add_option("--seed", bot.seed, "seed of the behaviour (bot k uses seed + k - 1)")
      ->capture_default_str();
  app.add_option("--bots", config.bots, "bots in this process, on one event loop")
      ->capture_default_str();
  app.add_option("--spacing-ms", spacing_ms, "ms between two bots' starts")->capture_default_str();
  app.add_option("--rebind-after-s", bot.rebind_after_s,
                 "move to a new local UDP port after this many seconds of connection; 0: never")
      ->capture_default_str();
  app.add_option("--matches", bot.matches, "stop after this many match results; 0: no limit")
      ->capture_default_str();
  app.add_option("--max-reconnects", bot.max_reconnect_attempts,
                 "failed attempts in a row before a bot gives up")
      ->capture_default_str();
  app.add_option("--sim-latency-ms", bot.link.latency_ms,
                 "simulated one-way latency of the game channel, each way, 0..5000")
      ->capture_default_str();
  app.add_option("--sim-jitter-ms", bot.link.jitter_ms,
                 "simulated jitter: each datagram's delay is latency +- up to this (uniform)")
      ->capture_default_str();
  app.add_option("--sim-loss", bot.link.loss, "simulated loss probability each way, 0..1")
      ->capture_default_str();
  app.add_option("--sim-duplicate", bot.link.duplicate,
                 "simulated probability a datagram arrives twice, 0..1")
      ->capture_default_str();
  app.add_option("--sim-reorder", bot.link.reorder,
                 "simulated probability a datagram is held back behind later ones, 0..1")
      ->capture_default_str();
  bool cheap = false;
  app.add_flag("--cheap", cheap, "no prediction or interpolation (load tests)");
  app.add_option("--dump-states", bot.dump_states,
                 "write every decoded snapshot's players to this CSV file (tick,entity,x,y,z); "
                 "with --bots N, bot k writes FILE-k");
  app.add_option("--duration-s", duration_s, "stop after this many seconds; 0: no limit")
      ->capture_default_str();
  app.add_option("--log-level", log_level, "trace|debug|info|warn|error|off (on stderr)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  config.start_spacing = std::chrono::milliseconds(spacing_ms);
  bot.predict = !cheap;
  if (const std::string problem = config.validate(); !problem.empty()) {
    std::fprintf(stderr, "ricochet-bot: %s\n", problem.c_str());
    return 2;
  }
  if (!(duration_s >= 0)) {
    std::fprintf(stderr, "ricochet-bot: --duration-s must be >= 0, got %g\n", duration_s);
    return 2;
  }
  spdlog::set_default_logger(spdlog::stderr_color_mt("ricochet-bot"));
  spdlog::set_level(spdlog::level::from_str(log_level));

  boost::asio::io_context io;
  Fleet fleet(io, config);
  boost::asio::signal_set signals(io, SIGINT, SIGTERM);
  boost::asio::steady_timer duration(io);
  signals.async_wait([&](const boost::system::error_code& error, int signal) {
    if (!error) fleet.stop(signal == SIGINT ? "SIGINT" : "SIGTERM");
  });
  if (duration_s > 0) {
    duration.expires_after(std::chrono::milliseconds(static_cast<std::int64_t>(duration_s * 1000)));
    duration.async_wait([&](const boost::system::error_code& error) {
      if (!error) fleet.stop("duration reached");
    });
  }
  fleet.on_done([&] {
    signals.cancel();
    duration.cancel();
  });
  if (std::string error = fleet.start(); !error.empty()) {
    std::fprintf(stderr, "ricochet-bot: %s\n", error.c_str());
    return 1;
  }
  io.run();

  std::cout << fleet.report_json() << std::endl;
  for (const auto& each : fleet.bots()) {
    if (!each->record().error.empty()) return 1;
  }
  return 0;
}
