/// Arena bench: 64 players and 256 bullets in a walled arena with pillars, run once with the
/// full model (physics_props world, every body spinning and swept, bullets as rigid bodies that
/// also hit each other) and once with the arena_players profile (scene_profile.h: players
/// without spin, bullets as swept projectiles that never enter the contact pipeline), from
/// identical inputs: players are steered by the same scripted velocities, bullets fired on the
/// same schedule.
///
/// Prints one JSON line per model and a summary line with the cost ratio and what the profile
/// gives up: how far the players end from where the full model puts them, and how many bullet
/// hits on players each model counted. Of --repeat runs per model the median one is kept
/// (nearest rank: the lower middle of an even count).
///
///   arena-bench [--steps 600] [--repeat 3] [--out FILE]

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "arena_scene.h"
#include "harness.h"

namespace rp = ricochet::physics;
namespace bench = ricochet::bench;

int main(int argc, char** argv) {
  CLI::App app("Arena bench: the arena_players profile against the full model, same inputs");
  int steps = 600, repeat = 3;
  std::string out;
  app.add_option("--steps", steps, "steps per run")->check(CLI::Range(1, 1000000));
  app.add_option("--repeat", repeat, "runs per model; the median ms/step is kept")
      ->check(CLI::Range(1, 100));
  app.add_option("--out", out, "also append the JSON lines to this file");
  CLI11_PARSE(app, argc, argv);
  bench::ResultsOut results(out);
  if (!results.ok()) {
    std::fprintf(stderr, "arena-bench: cannot write %s\n", out.c_str());
    return 2;
  }

  bench::ArenaResult result[2];
  const bench::ArenaStep timed_step = [](rp::World& world) {
    const bench::Stopwatch step;
    (void)world.step(rp::Real(1) / 60);
    return step.elapsed_ms();
  };
  for (const bench::ArenaModel m : {bench::ArenaModel::Full, bench::ArenaModel::ArenaPlayers}) {
    std::vector<bench::ArenaResult> runs;
    for (int k = 0; k < repeat; ++k) runs.push_back(bench::run_arena(m, steps, timed_step));
    std::sort(runs.begin(), runs.end(),
              [](const bench::ArenaResult& x, const bench::ArenaResult& y) {
                return x.ms_per_step < y.ms_per_step;
              });
    result[static_cast<int>(m)] = runs[ricochet::stats::nearest_rank_index(runs.size(), 50)];
    const bench::ArenaResult& r = result[static_cast<int>(m)];
    results.write(bench::result_line("arena")
                      .text("model", bench::arena_model_name(m))
                      .integer("players", bench::kArenaPlayers)
                      .integer("projectiles", bench::kArenaBullets)
                      .integer("steps", steps)
                      .number("ms_per_step", r.ms_per_step, 5)
                      .integer("bullets_fired", r.fired)
                      .integer("bullet_hits_on_players", r.hits)
                      .object("profile", bench::JsonObject()
                                             .number("broad_phase_ms", r.phases.broad_phase_ms, 4)
                                             .number("narrow_phase_ms", r.phases.narrow_phase_ms, 4)
                                             .number("solve_ms", r.phases.solve_ms, 4)
                                             .number("integrate_ms", r.phases.integrate_ms, 4)
                                             .number("continuous_ms", r.phases.continuous_ms, 4)
                                             .number("projectiles_ms", r.phases.projectiles_ms, 4)
                                             .number("sleep_ms", r.phases.sleep_ms, 4)
                                             .number("events_ms", r.phases.events_ms, 4)));
  }
  const bench::ArenaResult& full = result[0];
  const bench::ArenaResult& lean = result[1];
  double mean_dev = 0, max_dev = 0;
  for (int i = 0; i < bench::kArenaPlayers; ++i) {
    const double d = static_cast<double>((full.final_players[i] - lean.final_players[i]).norm());
    mean_dev += d / bench::kArenaPlayers;
    max_dev = std::max(max_dev, d);
  }
  results.write(bench::result_line("arena")
                    .flag("summary", true)
                    .number("full_over_profile_cost", full.ms_per_step / lean.ms_per_step, 3)
                    .number("player_deviation_mean_m", mean_dev, 4)
                    .number("player_deviation_max_m", max_dev, 4)
                    .number("hit_rate_full", static_cast<double>(full.hits) / full.fired, 4)
                    .number("hit_rate_profile", static_cast<double>(lean.hits) / lean.fired, 4));
  return 0;
}
