/// Match bench: what one match's tick costs on a server, per phase, with N players fighting on a
/// map — every player sending one input per tick (strafing, aiming at the nearest other player,
/// firing the rifle, rockets and grenades in turn, now and then jumping), claiming the view tick
/// an interpolating client would show, and acknowledging snapshots ack_delay_ms late, as clients
/// behind a link would. It runs the real Match (server/include/ricochet/server/match.h) with fake
/// time and times each tick with the steady clock. One JSON line per player count:
///   tick_ms_p50, tick_ms_p99, tick_ms_max, tick_ms_avg   Match::tick for one step, snapshots
///                                                        built and encoded for every client;
///                                                        percentiles by nearest rank
///                                                        (ricochet/stats/percentile.h)
///   phase_ms                     the TickProfile phases, averaged
///   kbps_per_client              ServerPayload bytes per client
///   projectiles_avg              rockets and grenades in flight, averaged over the ticks
///   shots_per_s, kills           what the fight did
///   matches_per_core             how many such matches one core could tick at this rate
///   replay_speed_x               the match's recording played back (ricochet-replay's path):
///                                simulated seconds per wall second; replay_hashes_match
///   viewer_replay_speed_x        the same for the dashboard's replay (server/src/web/
///                                replay_frames.h: every tick's frame kept), and
///                                viewer_frames_mb, what those frames hold in memory (MiB)
///   payload_fnv1a                FNV-1a of every payload sent (account, reliable, bytes), warm-up
///                                included: equal before and after a change that keeps the output
/// then one line of lag-compensated hitscan throughput (LagCompensation::cast against the map
/// and 64 rewound players, interpolated between ticks): lag_shots_per_s_per_core.
///
///   match-bench [--players 16,32,64] [--seconds 10] [--rate 60] [--ack-delay-ms 100]
///               [--map server/maps/foundry.toml] [--matches 1] [--record FILE] [--out FILE]
///               [--clock steady|thread-cpu] [--lag-shots 200000] [--ticks-out FILE] [--ticks-out
///               FILE] [--cache-off LAYER,...] [--ack-spread-ticks 0] [--watch-hz 20]
/// --clock thread-cpu times the ticks by this thread's CPU time instead of the wall: the figure
/// to quote from a machine shared with other work (JSON "clock" says which).
/// --matches N ticks N matches in turn, as one server core does, and times every tick: a tick
/// among 60 matches finds less of its state in the caches than a lone match's does.
/// --cache-off switches snapshot encode cache layers off (proto::SnapshotCacheLayers; "all" for
/// the plain per-client encoder): the payload hash stays, the snapshot phase's cost shows each.
/// --record writes the last player count's recording to FILE (for ricochet-replay).
/// --ticks-out appends one JSON line per measured tick to FILE: players, tick, ms, the phases,
/// entities; where a tail comes from (a burst of new projectiles, a phase's spike).
/// --watch-hz N measures instead what the dashboard costs the tick. The live spectator feed
/// (live_frame.h): two matches with the same script ticked in turn (which goes first swaps every
/// tick), one with a viewer whose feed publishes at N Hz, each tick timed on the same clock; one
/// "match_watch" line per player count: both matches' tick_ms, watch_cost_ratio (watched mean /
/// unwatched mean, and of the p50s), the frames and what encoding them as JSON cost (timed apart:
/// it runs on a viewer's thread, not the tick's), and whether both matches ended in the same
/// state. The overview: its leader lookup once a second timed on the watched match
/// (leader_lookup_us_*), and overview_cost_ratio, 1 + that spread over a second's ticks / the
/// unwatched tick's mean.

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "frame_json.h"
#include "harness.h"
#include "replay_frames.h"
#include "ricochet/physics/scene_profile.h"
#include "ricochet/proto/entity_flags.h"
#include "ricochet/server/lag_compensation.h"
#include "ricochet/server/live_frame.h"
#include "ricochet/server/map.h"
#include "ricochet/server/match.h"
#include "ricochet/server/match_replay.h"
#include "ricochet/server/recording.h"
#include "ricochet/server/replay.h"
#include "ricochet/wire/game.pb.h"

namespace server = ricochet::server;
namespace proto = ricochet::proto;
namespace wire = ricochet::wire;
namespace bench = ricochet::bench;
namespace stats = ricochet::stats;

namespace {

using bench::steady_ns;
using bench::thread_cpu_ns;

struct Options {
  std::vector<int> players{16, 32, 64};
  double seconds = 10;
  int rate_hz = 60;
  int ack_delay_ms = 100;
  /// Player i acknowledges i % (spread + 1) ticks later than ack_delay_ms, as clients at
  /// different distances do.
  int ack_spread_ticks = 0;
  std::string map = "server/maps/foundry.toml";
  std::string out;
  std::string record;
  std::string ticks_out;         ///< one JSON line per measured tick, appended
  std::string clock = "steady";  ///< what times a tick: steady (wall) or thread-cpu
  int lag_shots = 200000;        ///< lag-compensated shots timed after the matches
  /// Matches ticked in turn, as a server's core does: each evicts the others' state from the
  /// caches, so a tick costs what it does among many matches rather than alone.
  int matches = 1;
  /// Snapshot encode cache layers switched off (SnapshotCacheLayers), to measure what each saves.
  std::vector<std::string> cache_off;
  /// > 0: measure the live feed's cost at this rate instead (watch_cost).
  int watch_hz = 0;
};

/// The cache layers left on when `off` names some (or "all") of them.
proto::SnapshotCacheLayers cache_layers(const std::vector<std::string>& off) {
  proto::SnapshotCacheLayers layers;
  for (const std::string& name : off) proto::switch_off_cache_layer(name, layers);  // CLI checked
  return layers;
}

/// The scripted fighters: each strafes, aims at the nearest other living player (where the
/// match last showed it), fires, and changes weapon every few seconds.
class Fighters {
 public:
  std::string payload(server::Match& match, int player, std::uint32_t sequence,
                      std::uint32_t ack_tick, std::uint32_t view_tick, double time_s) {
    wire::ClientPayload payload;
    wire::Input* input = payload.add_inputs();
    input->set_sequence(sequence);
    const int phase = static_cast<int>(time_s * 0.7 + player) % 4;
    input->set_move_forward(phase < 2 ? 127 : -60);
    input->set_move_right(phase % 2 == 0 ? 100 : -100);
    const auto me = match.entity_of(1000 + static_cast<std::uint64_t>(player));
    const auto states = match.entity_states();
    const ricochet::proto::EntityState* self = nullptr;
    for (const auto& state : states) {
      if (me && state.id == *me) self = &state;
    }
    float yaw = static_cast<float>(std::fmod(time_s * 0.5 + player, 6.0));
    float pitch = 0;
    if (self) {
      double best = 1e30;
      for (const auto& state : states) {
        const bool player_entity = (state.flags & proto::kEntityKindMask) == 0;
        if (state.id == self->id || !player_entity || (state.flags & proto::kEntityDead)) continue;
        const double dx = state.position_m[0] - self->position_m[0];
        const double dy = state.position_m[1] - self->position_m[1];
        const double dz = state.position_m[2] - self->position_m[2];
        const double d2 = dx * dx + dy * dy + dz * dz;
        if (d2 < best) {
          best = d2;
          yaw = static_cast<float>(std::atan2(-dx, -dz));
          pitch = static_cast<float>(std::atan2(dy - 0.25, std::hypot(dx, dz)));
        }
      }
    }
    input->set_yaw(yaw);
    input->set_pitch(std::clamp(pitch, -1.5f, 1.5f));
    const int weapon = static_cast<int>(time_s / 3 + player) % 3;
    input->set_weapon_slot(static_cast<std::uint32_t>(weapon + 1));
    std::uint32_t buttons = proto::kButtonFire;
    if (sequence % (60 + player % 30) == 0) buttons |= proto::kButtonJump;
    input->set_buttons(buttons);
    input->set_view_tick(view_tick);
    payload.set_ack_snapshot_tick(ack_tick);
    return payload.SerializeAsString();
  }
};

/// One measured tick as a JSON line: its time, the profile's phases and the entity count.
void write_tick(std::ofstream& out, int players, int tick, double elapsed_ms,
                const server::Match& match) {
  const server::TickProfile& p = match.profile();
  char line[512];
  std::snprintf(line, sizeof line,
                "{\"players\":%d,\"tick\":%d,\"ms\":%.4f,\"apply_inputs\":%.4f,\"rules\":%.4f,"
                "\"movement\":%.4f,\"combat\":%.4f,\"physics\":%.4f,\"history\":%.4f,"
                "\"snapshots\":%.4f,\"send\":%.4f,\"entities\":%zu}",
                players, tick, elapsed_ms, p.apply_inputs_ms, p.rules_ms, p.movement_ms,
                p.combat_ms, p.physics_ms, p.history_ms, p.snapshots_ms, p.send_ms,
                match.entity_states().size());
  out << line << '\n';
}

/// FNV-1a over every byte the match sends, to show an optimisation leaves the output unchanged.
class Fnv1a {
 public:
  void add(std::uint64_t value) {
    for (int k = 0; k < 8; ++k) add_byte(static_cast<std::uint8_t>(value >> (8 * k)));
  }
  void add_byte(std::uint8_t byte) {
    hash_ ^= byte;
    hash_ *= 1099511628211ull;
  }
  std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 14695981039346656037ull;
};

/// A match of the bench and what its owner keeps of it.
struct BenchMatch {
  server::Match match;
  Fighters fighters;
};

/// Every player's input for step `t` at `now`, acknowledging snapshots ack_delay_ms late (player
/// i, i % (ack_spread_ticks + 1) ticks later still) and claiming the view tick an interpolating
/// client shows, about two snapshots behind what it received.
void send_inputs(BenchMatch& bench, int players, int t, proto::TimeUs now, const Options& options) {
  server::Match& match = bench.match;
  const std::uint32_t ack_delay_ticks =
      static_cast<std::uint32_t>(options.ack_delay_ms * options.rate_hz / 1000);
  for (int i = 0; i < players; ++i) {
    const std::uint32_t delay =
        ack_delay_ticks + static_cast<std::uint32_t>(i % (options.ack_spread_ticks + 1));
    const std::uint32_t ack = match.tick_number() > delay ? match.tick_number() - delay : 0;
    const std::uint32_t view = ack > 2 ? ack - 2 : 0;
    const std::string bytes =
        bench.fighters.payload(match, i, static_cast<std::uint32_t>(t), ack, view, now / 1e6);
    match.receive(1000 + i,
                  std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
  }
}

server::Match create_match(const server::Map& map, int players, const Options& options) {
  server::MatchConfig config;
  config.max_players = players;
  config.tick.rate_hz = options.rate_hz;
  config.snapshot_rate_hz = options.rate_hz;
  config.rules.min_players = 1;
  config.rules.warmup_s = 0;
  config.rules.frag_limit = 0;  // fight for the whole run
  config.rules.time_limit_s = 0;
  config.rules.respawn_delay_s = 1;
  config.snapshot_cache_layers = cache_layers(options.cache_off);
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
    match.set_latency(1000 + i, 30'000 + 1000 * (i % 40));
  }
  return match;
}

bench::JsonObject run(const server::Map& map, int players, const Options& options) {
  // Every match plays the same script, so each sends what the first does; the figures are over
  // every match's ticks, the payload hash, kilobits, shots and the recording the first's.
  std::vector<BenchMatch> benches;
  for (int m = 0; m < options.matches; ++m)
    benches.push_back({create_match(map, players, options), {}});
  server::Match& match = benches.front().match;
  const proto::TimeUs tick_us = proto::kMicrosPerSecond / options.rate_hz;
  const int ticks = static_cast<int>(options.seconds * options.rate_hz);
  const int warmup = options.rate_hz;  // one second: spawn, first full snapshots
  std::vector<double> tick_ms;
  server::TickProfile sum;
  std::uint64_t payload_bytes = 0;
  std::uint64_t projectiles = 0;
  std::uint64_t shots_before = 0;
  std::uint64_t kills_before = 0;
  server::Outgoing outgoing;
  Fnv1a payload_hash;
  std::ofstream ticks_out;
  if (!options.ticks_out.empty()) ticks_out.open(options.ticks_out, std::ios::app);
  const auto tick_clock_ns = options.clock == "thread-cpu" ? thread_cpu_ns : steady_ns;
  for (int t = 1; t <= warmup + ticks; ++t) {
    const proto::TimeUs now = t * tick_us;
    for (BenchMatch& bench : benches) {
      server::Match& each = bench.match;
      const bool first = &each == &match;
      send_inputs(bench, players, t, now, options);
      const std::int64_t started = tick_clock_ns();
      each.tick(now);
      const double elapsed_ms = static_cast<double>(tick_clock_ns() - started) / 1e6;
      std::uint64_t bytes = 0;
      while (each.poll_outbox(outgoing)) {
        if (!first) continue;
        if (!outgoing.reliable) bytes += outgoing.bytes.size();
        payload_hash.add(outgoing.account);
        payload_hash.add(outgoing.reliable ? 1 : 0);
        for (const std::uint8_t byte : outgoing.bytes) payload_hash.add_byte(byte);
      }
      if (t <= warmup) continue;
      tick_ms.push_back(elapsed_ms);
      sum += each.profile();
      if (ticks_out) write_tick(ticks_out, players, t - warmup, elapsed_ms, each);
      if (!first) continue;
      payload_bytes += bytes;
      for (const auto& state : each.entity_states())
        projectiles += (state.flags & proto::kEntityKindMask) != 0;
    }
    if (t == warmup) {
      shots_before = match.counters().shots_fired;
      kills_before = match.counters().kills;
    }
  }
  const stats::Summary tick = stats::summarize(tick_ms);
  const double n = static_cast<double>(tick.count);
  const double kbps = static_cast<double>(payload_bytes) * 8 / 1000 / options.seconds / players;
  const double period_ms = 1000.0 / options.rate_hz;
  const server::MatchCounters& counters = match.counters();
  // The recording, played back as ricochet-replay does.
  const std::vector<std::uint8_t> recording_bytes = match.take_recording();
  if (!options.record.empty()) {
    std::ofstream file(options.record, std::ios::binary | std::ios::trunc);
    file.write(reinterpret_cast<const char*>(recording_bytes.data()),
               static_cast<std::streamsize>(recording_bytes.size()));
  }
  double replay_speed = 0;
  bool replay_matches = false;
  double viewer_speed = 0;
  double viewer_mb = 0;
  auto read = server::read_recording(recording_bytes);
  if (auto* recording = std::get_if<server::Recording>(&read)) {
    auto opened = server::open_recorded_match(*recording);
    if (auto* replayed = std::get_if<server::Match>(&opened)) {
      server::MatchSimulation simulation(*replayed);
      server::ReplayOptions replay_options;
      replay_options.wall_clock_s = [] { return static_cast<double>(steady_ns()) / 1e9; };
      const server::ReplayReport report = server::replay(*recording, simulation, replay_options);
      replay_speed = report.wall_s > 0 ? report.simulated_s / report.wall_s : 0;
      replay_matches = !report.first_mismatch && report.hashes_checked > 0;
      server::ReplayProgress progress;
      const std::int64_t viewer_start_ns = steady_ns();
      auto viewed = server::replay_frames(*recording, progress, std::size_t{1} << 32);
      const double viewer_s = static_cast<double>(steady_ns() - viewer_start_ns) / 1e9;
      if (auto* frames = std::get_if<server::ReplayFrames>(&viewed)) {
        viewer_speed = viewer_s > 0 ? frames->report.simulated_s / viewer_s : 0;
        viewer_mb = static_cast<double>(frames->bytes()) / (1 << 20);
      } else {
        std::fprintf(stderr, "match-bench: viewer: %s\n", std::get<std::string>(viewed).c_str());
      }
    } else {
      std::fprintf(stderr, "match-bench: %s\n", std::get<std::string>(opened).c_str());
    }
  } else {
    std::fprintf(stderr, "match-bench: recording: %s\n",
                 std::get<server::RecordingError>(read).message.c_str());
  }
  const double player_minutes = players * (options.seconds + 1) / 60.0;
  char payload_fnv1a[17];
  std::snprintf(payload_fnv1a, sizeof payload_fnv1a, "%016llx",
                static_cast<unsigned long long>(payload_hash.value()));
  return bench::result_line("match")
      .text("map", map.name)
      .integer("players", players)
      .integer("matches", options.matches)
      .integer("rate_hz", options.rate_hz)
      .general("seconds", options.seconds)
      .integer("ack_delay_ms", options.ack_delay_ms)
      .text("clock", options.clock)
      .number("tick_ms_p50", tick.p50, 4)
      .number("tick_ms_p99", tick.p99, 4)
      .number("tick_ms_max", tick.max, 4)
      .number("tick_ms_avg", tick.mean, 4)
      .object("phase_ms", bench::JsonObject()
                              .number("apply_inputs", sum.apply_inputs_ms / n, 4)
                              .number("rules", sum.rules_ms / n, 4)
                              .number("movement", sum.movement_ms / n, 4)
                              .number("combat", sum.combat_ms / n, 4)
                              .number("physics", sum.physics_ms / n, 4)
                              .number("history", sum.history_ms / n, 4)
                              .number("snapshots", sum.snapshots_ms / n, 4)
                              .number("send", sum.send_ms / n, 4))
      .number("kbps_per_client", kbps, 1)
      .number("projectiles_avg", static_cast<double>(projectiles) * options.matches / n, 1)
      .number("shots_per_s",
              static_cast<double>(counters.shots_fired - shots_before) / options.seconds, 1)
      .integer("kills", counters.kills - kills_before)
      .integer("explosions", counters.explosions)
      .integer("recording_bytes", recording_bytes.size())
      .number("recording_bytes_per_player_minute",
              static_cast<double>(recording_bytes.size()) / player_minutes, 0)
      .number("replay_speed_x", replay_speed, 1)
      .flag("replay_hashes_match", replay_matches)
      .number("viewer_replay_speed_x", viewer_speed, 1)
      .number("viewer_frames_mb", viewer_mb, 2)
      .number("matches_per_core", period_ms / tick.mean, 1)
      .integer("overruns", counters.overruns)
      .text("payload_fnv1a", payload_fnv1a);
}

/// The live feed's cost to the tick: the same fight twice, ticked in turn, one watched.
bench::JsonObject watch_cost(const server::Map& map, int players, const Options& options) {
  BenchMatch plain{create_match(map, players, options), {}};
  BenchMatch watched{create_match(map, players, options), {}};
  server::LiveFeedConfig feed_config;
  feed_config.rate_hz = options.watch_hz;
  auto feed = std::make_shared<server::LiveFeed>(feed_config);
  watched.match.set_live_feed(feed);
  std::optional<server::LiveFeed::Viewer> viewer = feed->watch();
  std::shared_ptr<const server::LiveFrame> shown;
  const proto::TimeUs tick_us = proto::kMicrosPerSecond / options.rate_hz;
  const int ticks = static_cast<int>(options.seconds * options.rate_hz);
  const int warmup = options.rate_hz;
  const auto tick_clock_ns = options.clock == "thread-cpu" ? thread_cpu_ns : steady_ns;
  std::vector<double> plain_ms, watched_ms, encode_ms, leader_ms;
  std::uint64_t frame_bytes = 0;
  server::Outgoing outgoing;
  std::string leader;  // what the overview shows, kept across lookups as MatchHost keeps it
  for (int t = 1; t <= warmup + ticks; ++t) {
    const proto::TimeUs now = t * tick_us;
    for (int turn = 0; turn < 2; ++turn) {
      const bool watched_turn = (turn == 0) == (t % 2 == 0);
      BenchMatch& bench = watched_turn ? watched : plain;
      server::Match& match = bench.match;
      send_inputs(bench, players, t, now, options);
      const std::int64_t started = tick_clock_ns();
      match.tick(now);
      const double elapsed_ms = static_cast<double>(tick_clock_ns() - started) / 1e6;
      while (match.poll_outbox(outgoing)) {
      }
      if (t > warmup) (watched_turn ? watched_ms : plain_ms).push_back(elapsed_ms);
      // The overview's share, on the match's strand once a second: MatchHost::find_leader's
      // scan of the scoreboard (its per-tick copies of phase and tick are three loads).
      if (watched_turn && t > warmup && t % options.rate_hz == 0) {
        const std::int64_t leader_started = tick_clock_ns();
        int best = 0;
        leader.clear();
        for (const server::PlayerScore& score : match.scoreboard()) {
          if (score.score > best) {
            best = score.score;
            leader = score.name;
          }
        }
        leader_ms.push_back(static_cast<double>(tick_clock_ns() - leader_started) / 1e6);
      }
    }
    // The viewer's side: each new frame encoded once, as a page's stream would.
    std::shared_ptr<const server::LiveFrame> frame = viewer->latest();
    if (t > warmup && frame && frame != shown) {
      const std::int64_t started = tick_clock_ns();
      const std::string json = server::web::frame_json(*frame);
      encode_ms.push_back(static_cast<double>(tick_clock_ns() - started) / 1e6);
      frame_bytes += json.size();
      shown = std::move(frame);
    }
  }
  const stats::Summary unwatched = stats::summarize(plain_ms);
  const stats::Summary with_viewer = stats::summarize(watched_ms);
  const stats::Summary encode = stats::summarize(encode_ms);
  const stats::Summary leader_lookup = stats::summarize(leader_ms);
  return bench::result_line("match_watch")
      .text("map", map.name)
      .integer("players", players)
      .integer("rate_hz", options.rate_hz)
      .integer("watch_hz", options.watch_hz)
      .general("seconds", options.seconds)
      .text("clock", options.clock)
      .number("tick_ms_avg_unwatched", unwatched.mean, 4)
      .number("tick_ms_avg_watched", with_viewer.mean, 4)
      .number("tick_ms_p50_unwatched", unwatched.p50, 4)
      .number("tick_ms_p50_watched", with_viewer.p50, 4)
      .number("tick_ms_p99_unwatched", unwatched.p99, 4)
      .number("tick_ms_p99_watched", with_viewer.p99, 4)
      .number("watch_cost_ratio", with_viewer.mean / unwatched.mean, 4)
      .number("watch_cost_ratio_p50", with_viewer.p50 / unwatched.p50, 4)
      .integer("frames", encode.count)
      .number("encode_ms_avg", encode.mean, 4)
      .number("encode_ms_p99", encode.p99, 4)
      .number(
          "frame_bytes_avg",
          encode.count ? static_cast<double>(frame_bytes) / static_cast<double>(encode.count) : 0.0,
          0)
      .number("leader_lookup_us_avg", leader_lookup.mean * 1000, 2)
      .number("leader_lookup_us_max", leader_lookup.max * 1000, 2)
      .number("overview_cost_ratio", 1 + leader_lookup.mean / options.rate_hz / unwatched.mean, 6)
      .flag("same_state", plain.match.state_hash() == watched.match.state_hash());
}

/// Lag-compensated rays per second on one core: 64 players moving on the map, one second of
/// history, casts at random view times within the last 250 ms towards random players.
bench::JsonObject lag_shots(const server::Map& map, const Options& options) {
  auto world = ricochet::physics::World::create(ricochet::physics::profiles::arena_players());
  if (!world.ok() || !server::add_map_to_world(map, world.value()).ok()) {
    std::fprintf(stderr, "match-bench: cannot build the map's world\n");
    std::exit(1);
  }
  server::LagCompensationConfig config;
  server::LagCompensation lag(config, options.rate_hz);
  constexpr int kPlayers = 64;
  std::vector<server::LagSample> samples(kPlayers);
  std::uint64_t seed = 12345;
  const auto uniform = [&seed] {
    seed = seed * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<float>((seed >> 40) & 0xFFFFFF) / float(1 << 24);
  };
  std::vector<ricochet::physics::Vec3> base(kPlayers);
  for (int i = 0; i < kPlayers; ++i) {
    const auto& spawn = map.spawns[static_cast<std::size_t>(i) % map.spawns.size()];
    base[static_cast<std::size_t>(i)] = spawn.position_m;
  }
  const std::uint32_t ticks = static_cast<std::uint32_t>(options.rate_hz);
  for (std::uint32_t tick = 1; tick <= ticks; ++tick) {
    for (int i = 0; i < kPlayers; ++i) {
      const float t = static_cast<float>(tick) / static_cast<float>(options.rate_hz);
      samples[static_cast<std::size_t>(i)] = server::LagSample{
          static_cast<std::uint32_t>(i + 1),
          ricochet::physics::BodyId{},
          base[static_cast<std::size_t>(i)] +
              ricochet::physics::Vec3(std::sin(t * 3 + i) * 2, 0, std::cos(t * 2 + i) * 2),
          0.4f,
          1,
          true};
    }
    lag.record(tick, samples);
  }
  const int shots = options.lag_shots;
  int hits = 0;
  const std::int64_t started = steady_ns();
  for (int k = 0; k < shots; ++k) {
    const int shooter = k % kPlayers;
    const int target = (k * 7 + 3) % kPlayers;
    const auto& from = samples[static_cast<std::size_t>(shooter)].position_m;
    const auto& to = samples[static_cast<std::size_t>(target)].position_m;
    const auto view = lag.resolve(ticks, ticks - 1 - static_cast<std::uint32_t>(uniform() * 12),
                                  static_cast<std::uint8_t>(uniform() * 255), 40.0);
    ricochet::physics::RayHit hit;
    const ricochet::physics::Vec3 direction = (to - from).normalized();
    if (lag.cast(world.value(), from + ricochet::physics::Vec3(0, 0.25f, 0), direction, 200, view,
                 static_cast<std::uint32_t>(shooter + 1), hit) &&
        hit.target.user_data != 0) {
      ++hits;  // a player, not the map
    }
  }
  const double seconds = static_cast<double>(steady_ns() - started) / 1e9;
  return bench::result_line("lag_compensated_shots")
      .text("map", map.name)
      .integer("players", kPlayers)
      .integer("shots", shots)
      .integer("player_hits", hits)
      .number("us_per_shot", seconds * 1e6 / shots, 3)
      .number("lag_shots_per_s_per_core", shots / seconds, 0);
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  CLI::App app{"match-bench: one match's tick cost per phase with N players"};
  app.add_option("--players", options.players, "player counts, one line each")
      ->delimiter(',')
      ->check(CLI::Range(1, 64));
  app.add_option("--seconds", options.seconds, "measured seconds of match time")
      ->check(CLI::Range(0.1, 600.0));
  app.add_option("--rate", options.rate_hz, "tick and snapshot rate, Hz")
      ->check(CLI::Range(10, 128));
  app.add_option("--ack-delay-ms", options.ack_delay_ms, "how late clients acknowledge snapshots")
      ->check(CLI::Range(0, 1000));
  app.add_option("--ack-spread-ticks", options.ack_spread_ticks,
                 "player i acknowledges i % (N + 1) ticks later still (clients at different "
                 "distances; 0: all alike)")
      ->check(CLI::Range(0, 60));
  app.add_option("--watch-hz", options.watch_hz,
                 "measure the live spectator feed's cost to the tick at this rate instead: one "
                 "match_watch line per player count (0: off)")
      ->check(CLI::Range(0, 60));
  app.add_option("--map", options.map, "map file");
  app.add_option("--matches", options.matches,
                 "matches ticked in turn (each tick timed; figures over all of them)")
      ->check(CLI::Range(1, 256));
  app.add_option("--lag-shots", options.lag_shots, "lag-compensated shots to time")
      ->check(CLI::Range(1, 100000000));
  app.add_option("--out", options.out, "also append the JSON lines to this file");
  app.add_option("--record", options.record, "write the (last) match's recording to this file");
  app.add_option("--ticks-out", options.ticks_out,
                 "append one JSON line per measured tick (time, phases, entities) to this file");
  app.add_option("--clock", options.clock,
                 "what times each tick: steady (wall time) or thread-cpu (this thread's CPU time, "
                 "which leaves out other processes on a shared machine)")
      ->check(CLI::IsMember({"steady", "thread-cpu"}));
  app.add_option("--cache-off", options.cache_off,
                 "snapshot encode cache layers to switch off (the bytes stay the same): streams, "
                 "deltas, world_baselines, walks, whole_world_start or all")
      ->delimiter(',')
      ->check(CLI::Validator(
          [](const std::string& name) {
            proto::SnapshotCacheLayers layers;
            return proto::switch_off_cache_layer(name, layers) ? std::string{}
                                                               : "unknown layer " + name;
          },
          "LAYER"));
  CLI11_PARSE(app, argc, argv);

  auto loaded = server::load_map_file(options.map);
  if (auto* error = std::get_if<server::MapError>(&loaded)) {
    std::fprintf(stderr, "match-bench: %s: %s\n", options.map.c_str(), error->describe().c_str());
    return 1;
  }
  const server::Map& map = std::get<server::Map>(loaded);
  bench::ResultsOut results(options.out);
  if (!results.ok()) {
    std::fprintf(stderr, "match-bench: cannot write %s\n", options.out.c_str());
    return 1;
  }
  if (options.watch_hz > 0) {
    for (int players : options.players) results.write(watch_cost(map, players, options));
    return 0;
  }
  for (int players : options.players) results.write(run(map, players, options));
  results.write(lag_shots(map, options));
  return 0;
}
