/// Arena bench: 64 players and 256 bullets in a walled arena with pillars, run once with the
/// full model (physics_props world, every body spinning and swept, bullets as rigid bodies that
/// also hit each other) and once with the arena_players profile (scene_profile.h: players
/// without spin, bullets as swept projectiles that never enter the contact pipeline), from
/// identical inputs: players are steered by the same scripted velocities, bullets fired on the
/// same schedule.
///
/// Prints one JSON line per model and a summary line with the cost ratio and what the profile
/// gives up: how far the players end from where the full model puts them, and how many bullet
/// hits on players each model counted.
///
///   arena-bench [--steps 600] [--repeat 3]

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

#include "arena_scene.h"

namespace rp = ricochet::physics;
namespace bench = ricochet::bench;

int main(int argc, char** argv) {
  CLI::App app("Arena bench: the arena_players profile against the full model, same inputs");
  int steps = 600, repeat = 3;
  app.add_option("--steps", steps, "steps per run")->check(CLI::Range(1, 1000000));
  app.add_option("--repeat", repeat, "runs per model; the median ms/step is kept")
      ->check(CLI::Range(1, 100));
  CLI11_PARSE(app, argc, argv);

  bench::ArenaResult result[2];
  const bench::ArenaStep timed_step = [](rp::World& world) {
    const auto t0 = std::chrono::steady_clock::now();
    (void)world.step(rp::Real(1) / 60);
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  };
  for (const bench::ArenaModel m : {bench::ArenaModel::Full, bench::ArenaModel::ArenaPlayers}) {
    std::vector<bench::ArenaResult> runs;
    for (int k = 0; k < repeat; ++k) runs.push_back(bench::run_arena(m, steps, timed_step));
    std::sort(runs.begin(), runs.end(),
              [](const bench::ArenaResult& x, const bench::ArenaResult& y) {
                return x.ms_per_step < y.ms_per_step;
              });
    result[static_cast<int>(m)] = runs[runs.size() / 2];
    const bench::ArenaResult& r = result[static_cast<int>(m)];
    std::printf(
        "{\"bench\":\"arena\",\"model\":\"%s\",\"players\":%d,\"projectiles\":%d,\"steps\":%d,"
        "\"ms_per_step\":%.5f,\"bullets_fired\":%d,\"bullet_hits_on_players\":%d,\"profile\":{"
        "\"broad_phase_ms\":%.4f,"
        "\"narrow_phase_ms\":%.4f,\"solve_ms\":%.4f,\"integrate_ms\":%.4f,\"continuous_ms\":%.4f,"
        "\"projectiles_ms\":%.4f,\"sleep_ms\":%.4f,\"events_ms\":%.4f}}\n",
        bench::arena_model_name(m), bench::kArenaPlayers, bench::kArenaBullets, steps,
        r.ms_per_step, r.fired, r.hits, r.phases.broad_phase_ms, r.phases.narrow_phase_ms,
        r.phases.solve_ms, r.phases.integrate_ms, r.phases.continuous_ms, r.phases.projectiles_ms,
        r.phases.sleep_ms, r.phases.events_ms);
  }
  const bench::ArenaResult& full = result[0];
  const bench::ArenaResult& lean = result[1];
  double mean_dev = 0, max_dev = 0;
  for (int i = 0; i < bench::kArenaPlayers; ++i) {
    const double d = static_cast<double>((full.final_players[i] - lean.final_players[i]).norm());
    mean_dev += d / bench::kArenaPlayers;
    max_dev = std::max(max_dev, d);
  }
  std::printf(
      "{\"bench\":\"arena\",\"summary\":true,\"full_over_profile_cost\":%.3f,"
      "\"player_deviation_mean_m\":%.4f,\"player_deviation_max_m\":%.4f,"
      "\"hit_rate_full\":%.4f,\"hit_rate_profile\":%.4f}\n",
      full.ms_per_step / lean.ms_per_step, mean_dev, max_dev,
      static_cast<double>(full.hits) / full.fired, static_cast<double>(lean.hits) / lean.fired);
  return 0;
}
