/// Rewind bench: what a per-tick save and restore of the world costs on the arena scene (64
/// players and 256 bullets in the arena_players profile, a 20 000-triangle map mesh as the
/// floor), after warm-up.
///
///   rewind   StateParts::Dynamic into a reused buffer, restored in place into the same world
///   full     StateParts::All: the self-contained image, restored into a fresh world (the
///            configuration is read and the shapes' hierarchy rebuilt)
///
/// Prints one JSON line per mode: image bytes, bytes per moving body (players and live
/// projectiles), median µs per save and per restore over --repeat rounds (nearest rank: the
/// lower middle of an even count), and whether the state hash survives the round trip.
///
///   rewind-bench [--steps 120] [--repeat 200] [--out FILE]

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "arena_scene.h"
#include "harness.h"

namespace rp = ricochet::physics;
namespace bench = ricochet::bench;

namespace {

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
    bench::Stopwatch save;
    world.save_state(image, rp::StateParts::Dynamic);
    saves.push_back(save.elapsed_us());
    bench::Stopwatch restore;
    const rp::Status s = world.restore_state(image);
    restores.push_back(restore.elapsed_us());
    t.same_hash = t.same_hash && s.ok() && world.state_hash() == hash;
  }
  t.bytes = image.size();
  t.save_us = ricochet::stats::median(saves);
  t.restore_us = ricochet::stats::median(restores);
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
    bench::Stopwatch save;
    world.save_state(image, rp::StateParts::All);
    saves.push_back(save.elapsed_us());
    rp::World fresh = rp::World::create(world.definition()).value();
    bench::Stopwatch restore;
    const rp::Status s = fresh.restore_state(image);
    restores.push_back(restore.elapsed_us());
    t.same_hash = t.same_hash && s.ok() && fresh.state_hash() == hash;
  }
  t.bytes = image.size();
  t.save_us = ricochet::stats::median(saves);
  t.restore_us = ricochet::stats::median(restores);
  return t;
}

bench::JsonObject result(const char* mode, const Timing& t, std::uint32_t moving) {
  return bench::result_line("rewind")
      .text("mode", mode)
      .integer("players", bench::kArenaPlayers)
      .integer("projectiles", bench::kArenaBullets)
      .integer("mesh_triangles", bench::kArenaMeshTriangles)
      .integer("image_bytes", t.bytes)
      .number("bytes_per_moving_body", static_cast<double>(t.bytes) / moving, 1)
      .number("save_us", t.save_us, 2)
      .number("restore_us", t.restore_us, 2)
      .flag("same_hash", t.same_hash);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Rewind bench: per-tick save and restore of the arena scene with a map mesh");
  int steps = 120, repeat = 200;
  std::string out;
  app.add_option("--steps", steps, "warm-up steps before measuring")->check(CLI::Range(1, 100000));
  app.add_option("--repeat", repeat, "save/restore rounds; the median is kept")
      ->check(CLI::Range(20, 100000));
  app.add_option("--out", out, "also append the JSON lines to this file");
  CLI11_PARSE(app, argc, argv);
  bench::ResultsOut results(out);
  if (!results.ok()) {
    std::fprintf(stderr, "rewind-bench: cannot write %s\n", out.c_str());
    return 2;
  }

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
        results.write(result("rewind", rewind, moving));
        results.write(result("full", full, moving));
        ok = rewind.same_hash && full.same_hash;
        return 0.0;
      },
      bench::ArenaFloor::Mesh);
  return ok ? 0 : 1;
}
