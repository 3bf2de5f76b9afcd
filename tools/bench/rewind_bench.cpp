/// Rewind bench: what a per-tick save and restore of the world costs on the arena scene (64
/// players and 256 bullets in the arena_players profile, a 20 000-triangle map mesh as the
/// floor), after warm-up.
///
///   rewind   StateParts::Dynamic into a reused buffer, restored in place into the same world
///   full     StateParts::All: the self-contained image, restored into a fresh world (the
///            configuration is read and the shapes' hierarchy rebuilt)
///
/// Prints one JSON line per mode: image bytes, bytes per moving body (players and live
/// projectiles), median µs per save and per restore over --repeat rounds, and whether the state
/// hash survives the round trip.
///
///   rewind-bench [--steps 120] [--repeat 200]

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

#include "arena_scene.h"

namespace rp = ricochet::physics;
namespace bench = ricochet::bench;

namespace {

using Clock = std::chrono::steady_clock;

double us_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

struct Timing {
  std::size_t bytes = 0;
  double save_us = 0, restore_us = 0;
  bool same_hash = true;
};

Timing measure_rewind(rp::World& world, int repeat) {
  Timing t;
  std::vector<std::uint8_t> image;
  world.save_state(image, rp::StateParts::Dynamic);  // warm the buffer
  const std::uint64_t hash = world.state_hash();
  std::vector<double> saves, restores;
  for (int k = 0; k < repeat; ++k) {
    const auto t0 = Clock::now();
    world.save_state(image, rp::StateParts::Dynamic);
    saves.push_back(us_since(t0));
    const auto t1 = Clock::now();
    const rp::Status s = world.restore_state(image);
    restores.push_back(us_since(t1));
    t.same_hash = t.same_hash && s.ok() && world.state_hash() == hash;
  }
  t.bytes = image.size();
  t.save_us = median(saves);
  t.restore_us = median(restores);
  return t;
}

Timing measure_full(rp::World& world, int repeat) {
  Timing t;
  std::vector<std::uint8_t> image;
  world.save_state(image, rp::StateParts::All);
  const std::uint64_t hash = world.state_hash();
  std::vector<double> saves, restores;
  const int rounds = std::max(1, repeat / 20);  // each restore rebuilds the hierarchy
  for (int k = 0; k < rounds; ++k) {
    const auto t0 = Clock::now();
    world.save_state(image, rp::StateParts::All);
    saves.push_back(us_since(t0));
    rp::World fresh = rp::World::create(world.definition()).value();
    const auto t1 = Clock::now();
    const rp::Status s = fresh.restore_state(image);
    restores.push_back(us_since(t1));
    t.same_hash = t.same_hash && s.ok() && fresh.state_hash() == hash;
  }
  t.bytes = image.size();
  t.save_us = median(saves);
  t.restore_us = median(restores);
  return t;
}

void report(const char* mode, const Timing& t, std::uint32_t moving) {
  std::printf(
      "{\"bench\":\"rewind\",\"mode\":\"%s\",\"players\":%d,\"projectiles\":%d,"
      "\"mesh_triangles\":%d,\"image_bytes\":%zu,\"bytes_per_moving_body\":%.1f,"
      "\"save_us\":%.2f,\"restore_us\":%.2f,\"same_hash\":%s}\n",
      mode, bench::kArenaPlayers, bench::kArenaBullets, bench::kArenaMeshTriangles, t.bytes,
      static_cast<double>(t.bytes) / moving, t.save_us, t.restore_us,
      t.same_hash ? "true" : "false");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Rewind bench: per-tick save and restore of the arena scene with a map mesh");
  int steps = 120, repeat = 200;
  app.add_option("--steps", steps, "warm-up steps before measuring")->check(CLI::Range(1, 100000));
  app.add_option("--repeat", repeat, "save/restore rounds; the median is kept")
      ->check(CLI::Range(20, 100000));
  CLI11_PARSE(app, argc, argv);

  bool ok = true;
  int step = 0;
  bench::run_arena(
      bench::ArenaModel::ArenaPlayers, steps,
      [&](rp::World& world) {
        (void)world.step(rp::Real(1) / 60);
        if (++step < steps) return 0.0;
        const std::uint32_t moving = world.body_count() + world.projectile_count();
        const Timing rewind = measure_rewind(world, repeat);
        const Timing full = measure_full(world, repeat);
        report("rewind", rewind, moving);
        report("full", full, moving);
        ok = rewind.same_hash && full.same_hash;
        return 0.0;
      },
      bench::ArenaFloor::Mesh);
  return ok ? 0 : 1;
}
