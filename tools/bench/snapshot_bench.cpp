/// Snapshot bench: what the snapshot codec (proto/snapshot_codec.h) costs per client on three
/// scenes, each run through the real encoder and decoder with the client's acknowledgements
/// arriving ack_delay_ms late.
///
///   spheres901  Fiedler's cube demo with spheres: 900 spheres (0.5 m) resting in a 30 x 30 grid
///               (1.3 m apart) on a floor, one large kinematic sphere (2.5 m radius) driven
///               through them on a figure of eight at up to 4 m/s. Spheres and floor resist
///               rolling, so a knocked sphere rolls a metre or two and rests.
///   spheres901_dense  the same with the grid 1.05 m apart: the ball ploughs a crowd ahead of it,
///               several times as many spheres move, and the budget binds.
///   players16, players64  arena_players movement: players running on scripted headings, each
///               client seeing every player, priority from its own position.
///
/// Each scene runs a warm-up (the client receives the world, not measured), a rest phase
/// (nothing moves; bits_per_entity_rest) and the measured run (rate_hz x seconds snapshots).
/// Sizes are the serialised wire::Snapshot, its protobuf header included. `mismatches` counts
/// decoded entities that differ from the server's quantised state in snapshots the encoder
/// sent complete (deferred_snapshots counts the others, where the budget left some out).
/// bits_per_entity_p99 is nearest rank (ricochet/stats/percentile.h) over every client's
/// snapshots of the run.
///
///   snapshot-bench [--seconds 20] [--rate 60] [--ack-delay-ms 100] [--budget 1100]
///                  [--scene all|spheres901|spheres901_dense|players16|players64] [--out FILE]
/// --out appends the JSON lines to FILE.

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <functional>
#include <string>
#include <vector>

#include "harness.h"
#include "ricochet/physics/world.h"
#include "ricochet/proto/snapshot_codec.h"
#include "snapshot_scenes.h"

namespace rp = ricochet::physics;
namespace proto = ricochet::proto;
namespace bench = ricochet::bench;
namespace stats = ricochet::stats;

namespace {

struct BenchOptions {
  double seconds = 20;
  int rate_hz = 60;
  int ack_delay_ms = 100;
  std::size_t budget_bytes = 1100;
  float velocity_step_mps = 0.01f;
  int orientation_bits = 9;
};

/// One client: its encoder on the server, its decoder, the acks on their way back, and the
/// figures of the measured phases.
class ClientLink {
 public:
  ClientLink(const proto::QuantizationSpec& spec, int ack_delay_ticks)
      : encoder_(spec), decoder_(spec), ack_delay_ticks_(ack_delay_ticks) {}

  enum class Phase { Warmup, Rest, Run };

  void send(std::uint32_t tick, std::span<const proto::QuantizedEntity> world,
            std::array<float, 3> viewer_m, std::size_t budget_bytes, Phase phase) {
    while (!acks_.empty() && acks_.front().first <= tick) {
      encoder_.acknowledge(acks_.front().second);
      acks_.pop_front();
    }
    const auto t0 = std::chrono::steady_clock::now();
    encoder_.encode(tick, world, viewer_m, budget_bytes, snapshot_);
    const auto t1 = std::chrono::steady_clock::now();
    wire_ = snapshot_.SerializeAsString();
    received_.ParseFromString(wire_);
    const auto t2 = std::chrono::steady_clock::now();
    const proto::SnapshotDecodeResult result = decoder_.decode(received_);
    const auto t3 = std::chrono::steady_clock::now();
    if (!result.ok) {
      std::fprintf(stderr, "snapshot-bench: tick %u refused: %s\n", tick, result.message.c_str());
      ++refused_;
      return;
    }
    acks_.emplace_back(tick + ack_delay_ticks_, decoder_.newest_tick());
    if (phase == Phase::Warmup) return;

    const double bits_per_entity =
        8.0 * static_cast<double>(wire_.size()) / std::max<std::size_t>(1, world.size());
    if (phase == Phase::Rest) {
      rest_bits_.push_back(bits_per_entity);
    } else {
      run_bits_.push_back(bits_per_entity);
      run_bytes_ += wire_.size();
      encode_us_ += std::chrono::duration<double, std::micro>(t1 - t0).count();
      decode_us_ += std::chrono::duration<double, std::micro>(t3 - t2).count();
      pending_ += encoder_.last_report().pending;
      for (const proto::QuantizedEntity& e : world) {
        moving_ += e.velocity != std::array<std::int32_t, 3>{};
      }
    }
    if (encoder_.last_report().deferred > 0) {
      ++deferred_snapshots_;
      return;
    }
    if (result.entities.size() != world.size()) {
      mismatches_ += std::max(result.entities.size(), world.size());
      return;
    }
    for (std::size_t i = 0; i < world.size(); ++i) mismatches_ += !(result.entities[i] == world[i]);
  }

  const std::vector<double>& run_bits() const { return run_bits_; }
  const std::vector<double>& rest_bits() const { return rest_bits_; }
  std::size_t run_bytes() const { return run_bytes_; }
  double encode_us() const { return encode_us_; }
  double decode_us() const { return decode_us_; }
  std::uint64_t pending() const { return pending_; }
  std::uint64_t moving() const { return moving_; }
  std::uint64_t mismatches() const { return mismatches_; }
  std::uint64_t deferred_snapshots() const { return deferred_snapshots_; }
  std::uint64_t refused() const { return refused_; }

 private:
  proto::SnapshotEncoder encoder_;
  proto::SnapshotDecoder decoder_;
  int ack_delay_ticks_;
  std::deque<std::pair<std::uint32_t, std::uint32_t>> acks_;  ///< (arrives at tick, acked tick)
  ricochet::wire::Snapshot snapshot_, received_;
  std::string wire_;
  std::vector<double> run_bits_, rest_bits_;
  std::size_t run_bytes_ = 0;
  double encode_us_ = 0, decode_us_ = 0;
  std::uint64_t pending_ = 0, moving_ = 0, mismatches_ = 0, deferred_snapshots_ = 0, refused_ = 0;
};

using Scene = bench::SnapshotScene;

bench::JsonObject run(Scene scene, const BenchOptions& options) {
  scene.spec.velocity_step_mps = options.velocity_step_mps;
  scene.spec.orientation_bits = options.orientation_bits;
  scene.spec.tick_s = 1.0f / static_cast<float>(options.rate_hz);
  if (const std::string problem = scene.spec.validate(); !problem.empty()) {
    std::fprintf(stderr, "snapshot-bench: %s\n", problem.c_str());
    std::exit(2);
  }
  const int ack_delay_ticks =
      static_cast<int>(std::lround(options.ack_delay_ms * options.rate_hz / 1000.0));
  std::vector<ClientLink> links;
  for (int c = 0; c < scene.clients; ++c) links.emplace_back(scene.spec, ack_delay_ticks);
  const int warmup_steps = options.rate_hz * 3 / 2;
  const int rest_steps = options.rate_hz;
  const int run_steps = static_cast<int>(std::lround(options.seconds * options.rate_hz));
  const rp::Real dt = rp::Real(1) / options.rate_hz;
  std::vector<proto::QuantizedEntity> entities;
  std::uint32_t tick = 0;
  for (int step = 0; step < warmup_steps + rest_steps + run_steps; ++step) {
    const bool moving = step >= warmup_steps + rest_steps;
    const ClientLink::Phase phase = step < warmup_steps ? ClientLink::Phase::Warmup
                                    : moving            ? ClientLink::Phase::Run
                                                        : ClientLink::Phase::Rest;
    scene.drive(scene, step - warmup_steps - rest_steps, moving);
    (void)scene.world.step(dt);
    bench::read_entities(scene, entities);
    ++tick;
    for (int c = 0; c < scene.clients; ++c) {
      links[c].send(tick, entities, scene.viewer(scene, c), options.budget_bytes, phase);
    }
  }

  std::vector<double> run_bits, rest_bits;
  std::size_t run_bytes = 0;
  double encode_us = 0, decode_us = 0;
  std::uint64_t pending = 0, moving = 0, mismatches = 0, deferred = 0, refused = 0;
  for (const ClientLink& link : links) {
    run_bits.insert(run_bits.end(), link.run_bits().begin(), link.run_bits().end());
    rest_bits.insert(rest_bits.end(), link.rest_bits().begin(), link.rest_bits().end());
    run_bytes += link.run_bytes();
    encode_us += link.encode_us();
    decode_us += link.decode_us();
    pending += link.pending();
    moving += link.moving();
    mismatches += link.mismatches();
    deferred += link.deferred_snapshots();
    refused += link.refused();
  }
  const double snapshots = static_cast<double>(run_bits.size());
  const double kbps = run_bytes * 8.0 / snapshots * options.rate_hz / 1000.0;
  return bench::result_line("snapshot")
      .text("scene", scene.name)
      .integer("entities", scene.bodies.size())
      .integer("clients", scene.clients)
      .general("seconds", options.seconds)
      .integer("rate_hz", options.rate_hz)
      .integer("ack_delay_ms", options.ack_delay_ms)
      .integer("budget_bytes", options.budget_bytes)
      .general("velocity_step_mps", scene.spec.velocity_step_mps)
      .integer("orientation_bits", scene.spec.orientation_bits)
      .number("bits_per_entity_avg", stats::mean(run_bits), 3)
      .number("bits_per_entity_p99", stats::percentile(run_bits, 99), 3)
      .number("bits_per_entity_rest", stats::mean(rest_bits), 3)
      .number("bytes_per_snapshot_avg", run_bytes / snapshots, 1)
      .number("kbps_per_client", kbps, 2)
      .number("encode_us", encode_us / snapshots, 2)
      .number("decode_us", decode_us / snapshots, 2)
      .number("pending_per_snapshot", pending / snapshots, 1)
      .number("moving_per_snapshot", moving / snapshots, 1)
      .integer("mismatches", mismatches)
      .integer("deferred_snapshots", deferred)
      .integer("refused", refused);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Snapshot bench: bits per entity, kbps per client, encode/decode time");
  BenchOptions options;
  std::string scene = "all", out;
  app.add_option("--seconds", options.seconds, "measured run, s")->check(CLI::Range(0.1, 3600.0));
  app.add_option("--rate", options.rate_hz, "tick and snapshot rate, Hz")
      ->check(CLI::Range(10, 128));
  app.add_option("--ack-delay-ms", options.ack_delay_ms, "delay of the client's acks, ms")
      ->check(CLI::Range(0, 2000));
  app.add_option("--budget", options.budget_bytes, "bytes per snapshot")
      ->check(CLI::Range(16, 1200));
  app.add_option("--velocity-step", options.velocity_step_mps, "velocity quantum, m/s")
      ->check(CLI::Range(0.0001, 1.0));
  app.add_option("--orientation-bits", options.orientation_bits,
                 "bits per smallest-three component")
      ->check(CLI::Range(4, 16));
  app.add_option("--scene", scene, "all, spheres901, spheres901_dense, players16 or players64")
      ->check(CLI::IsMember({"all", "spheres901", "spheres901_dense", "players16", "players64"}));
  app.add_option("--out", out, "also append the JSON lines to this file");
  CLI11_PARSE(app, argc, argv);
  bench::ResultsOut results(out);
  if (!results.ok()) {
    std::fprintf(stderr, "snapshot-bench: cannot write %s\n", out.c_str());
    return 1;
  }

  std::vector<bench::JsonObject> lines;
  if (scene == "all" || scene == "spheres901") {
    lines.push_back(run(bench::spheres_scene("spheres901", bench::kSpheresSpacing), options));
  }
  if (scene == "all" || scene == "spheres901_dense") {
    lines.push_back(
        run(bench::spheres_scene("spheres901_dense", bench::kSpheresDenseSpacing), options));
  }
  if (scene == "all" || scene == "players16")
    lines.push_back(run(bench::players_scene(16), options));
  if (scene == "all" || scene == "players64")
    lines.push_back(run(bench::players_scene(64), options));
  for (const bench::JsonObject& line : lines) results.write(line);
  return 0;
}
