/// Match bench: what one match's tick costs on a server, per phase, with N players on the sample
/// map — every player sending one input per tick (running, turning, now and then jumping) and
/// acknowledging snapshots ack_delay_ms late, as clients behind a link would. It runs the real
/// Match (server/include/ricochet/server/match.h) with fake time and times each tick with the
/// steady clock. One JSON line per player count:
///   tick_ms_avg, tick_ms_p99       Match::tick for one step, snapshots included
///   phase_ms                       the TickProfile phases, averaged
///   kbps_per_client                ServerPayload bytes per client
///   matches_per_core               how many such matches one core could tick at this rate
///
///   match-bench [--players 16,64] [--seconds 10] [--rate 60] [--ack-delay-ms 100]
///               [--map server/maps/arena.toml] [--out FILE]

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "ricochet/server/map.h"
#include "ricochet/server/match.h"
#include "ricochet/wire/game.pb.h"

namespace server = ricochet::server;
namespace proto = ricochet::proto;
namespace wire = ricochet::wire;

namespace {

std::int64_t steady_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

struct Options {
  std::vector<int> players{16, 64};
  double seconds = 10;
  int rate_hz = 60;
  int ack_delay_ms = 100;
  std::string map = "server/maps/arena.toml";
  std::string out;
};

/// One player's input for `tick`: run forward, turn at a player-specific rate, jump now and then.
std::string input_payload(int player, std::uint32_t sequence, std::uint32_t ack_tick, double time_s) {
  wire::ClientPayload payload;
  wire::Input* input = payload.add_inputs();
  input->set_sequence(sequence);
  input->set_move_forward(127);
  input->set_move_right(player % 3 == 0 ? 40 : 0);
  const double turn = 0.5 + 0.1 * (player % 7);
  input->set_yaw(static_cast<float>(std::fmod(time_s * turn + player, 6.0)));
  input->set_buttons(sequence % (60 + player % 30) == 0 ? 1u : 0u);
  payload.set_ack_snapshot_tick(ack_tick);
  return payload.SerializeAsString();
}

std::string run(const server::Map& map, int players, const Options& options) {
  server::MatchConfig config;
  config.max_players = players;
  config.tick.rate_hz = options.rate_hz;
  config.snapshot_rate_hz = options.rate_hz;
  auto created = server::Match::create(config, map, 0, steady_ns);
  if (auto* error = std::get_if<std::string>(&created)) {
    std::fprintf(stderr, "match-bench: %s\n", error->c_str());
    std::exit(1);
  }
  server::Match match = std::move(std::get<server::Match>(created));
  for (int i = 0; i < players; ++i) {
    std::string name = "bot";  // (not "bot" + to_string: gcc 12's false -Wrestrict)
    name += std::to_string(i);
    if (!std::holds_alternative<server::Joined>(match.connect(1000 + i, name))) {
      std::fprintf(stderr, "match-bench: player %d was refused\n", i);
      std::exit(1);
    }
  }
  const proto::TimeUs tick_us = proto::kMicrosPerSecond / options.rate_hz;
  const std::uint32_t ack_delay_ticks =
      static_cast<std::uint32_t>(options.ack_delay_ms * options.rate_hz / 1000);
  const int ticks = static_cast<int>(options.seconds * options.rate_hz);
  const int warmup = options.rate_hz;  // one second: spawn, first full snapshots
  std::vector<double> tick_ms;
  server::TickProfile sum;
  std::uint64_t payload_bytes = 0;
  server::Outgoing outgoing;
  for (int t = 1; t <= warmup + ticks; ++t) {
    const proto::TimeUs now = t * tick_us;
    const std::uint32_t ack = match.tick_number() > ack_delay_ticks ? match.tick_number() - ack_delay_ticks : 0;
    for (int i = 0; i < players; ++i) {
      const std::string bytes = input_payload(i, static_cast<std::uint32_t>(t), ack, now / 1e6);
      match.receive(1000 + i, std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
    }
    const std::int64_t started = steady_ns();
    match.tick(now);
    const double elapsed_ms = static_cast<double>(steady_ns() - started) / 1e6;
    std::uint64_t bytes = 0;
    while (match.poll_outbox(outgoing)) {
      if (!outgoing.reliable) bytes += outgoing.bytes.size();
    }
    if (t <= warmup) continue;
    tick_ms.push_back(elapsed_ms);
    payload_bytes += bytes;
    const server::TickProfile& profile = match.profile();
    sum.apply_inputs_ms += profile.apply_inputs_ms;
    sum.movement_ms += profile.movement_ms;
    sum.physics_ms += profile.physics_ms;
    sum.history_ms += profile.history_ms;
    sum.snapshots_ms += profile.snapshots_ms;
    sum.send_ms += profile.send_ms;
  }
  std::vector<double> sorted = tick_ms;
  std::sort(sorted.begin(), sorted.end());
  double total = 0;
  for (double ms : tick_ms) total += ms;
  const double n = static_cast<double>(tick_ms.size());
  const double avg = total / n;
  const double p99 = sorted[static_cast<std::size_t>(n * 0.99)];
  const double kbps = static_cast<double>(payload_bytes) * 8 / 1000 / options.seconds / players;
  const double period_ms = 1000.0 / options.rate_hz;
  char line[1024];
  std::snprintf(line, sizeof line,
                "{\"bench\":\"match\",\"players\":%d,\"rate_hz\":%d,\"seconds\":%g,\"ack_delay_ms\":%d,"
                "\"tick_ms_avg\":%.4f,\"tick_ms_p99\":%.4f,\"phase_ms\":{\"apply_inputs\":%.4f,"
                "\"movement\":%.4f,\"physics\":%.4f,\"history\":%.4f,\"snapshots\":%.4f,\"send\":%.4f},"
                "\"kbps_per_client\":%.1f,\"matches_per_core\":%.1f,\"overruns\":%llu}",
                players, options.rate_hz, options.seconds, options.ack_delay_ms, avg, p99,
                sum.apply_inputs_ms / n, sum.movement_ms / n, sum.physics_ms / n, sum.history_ms / n,
                sum.snapshots_ms / n, sum.send_ms / n, kbps, period_ms / avg,
                static_cast<unsigned long long>(match.counters().overruns));
  return line;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  CLI::App app{"match-bench: one match's tick cost per phase with N players"};
  app.add_option("--players", options.players, "player counts, one line each")->delimiter(',')->check(CLI::Range(1, 64));
  app.add_option("--seconds", options.seconds, "measured seconds of match time")->check(CLI::Range(0.1, 600.0));
  app.add_option("--rate", options.rate_hz, "tick and snapshot rate, Hz")->check(CLI::Range(10, 128));
  app.add_option("--ack-delay-ms", options.ack_delay_ms, "how late clients acknowledge snapshots")->check(CLI::Range(0, 1000));
  app.add_option("--map", options.map, "map file");
  app.add_option("--out", options.out, "also append the JSON lines to this file");
  CLI11_PARSE(app, argc, argv);

  auto loaded = server::load_map_file(options.map);
  if (auto* error = std::get_if<server::MapError>(&loaded)) {
    std::fprintf(stderr, "match-bench: %s: %s\n", options.map.c_str(), error->describe().c_str());
    return 1;
  }
  const server::Map& map = std::get<server::Map>(loaded);
  std::ofstream out;
  if (!options.out.empty()) out.open(options.out, std::ios::app);
  for (int players : options.players) {
    const std::string line = run(map, players, options);
    std::printf("%s\n", line.c_str());
    if (out) out << line << '\n';
  }
  return 0;
}
