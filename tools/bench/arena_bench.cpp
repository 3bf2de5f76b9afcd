/// Arena bench: 64 players and 256 projectiles in a walled arena with pillars, run once with the
/// full model (physics_props world, every body spinning and swept, projectiles hitting each
/// other) and once with the arena_players profile (scene_profile.h), from identical inputs:
/// players are steered by the same scripted velocities, projectiles fired on the same schedule.
///
/// Prints one JSON line per model and a summary line with the cost ratio and what the profile
/// gives up: how far the players end from where the full model puts them, and how many
/// projectile hits on players each model counted.
///
///   arena-bench [--steps 600] [--repeat 3]

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "ricochet/physics/scene_profile.h"
#include "ricochet/physics/world.h"

namespace rp = ricochet::physics;
namespace profiles = ricochet::physics::profiles;

namespace {

constexpr int kPlayers = 64;
constexpr int kProjectiles = 256;
constexpr rp::Real kHalfWidth = 20;         ///< m, arena half extent
constexpr rp::Real kPlayerSpeed = 6;        ///< m/s, scripted run speed
constexpr rp::Real kProjectileSpeed = 300;  ///< m/s

enum class Model { Full, ArenaPlayers };

const char* model_name(Model m) {
  return m == Model::Full ? "full" : "arena_players";
}

/// Deterministic pseudo-random numbers (the same sequence for both models).
struct Lcg {
  std::uint64_t state;
  double next() {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) * 0x1.0p-53;
  }
};

struct Arena {
  rp::World world;
  std::vector<rp::BodyId> players;
  std::vector<rp::BodyId> projectiles;
};

rp::BodyDef player_def(Model m, const rp::Vec3& p) {
  rp::BodyDef def = profiles::player(p);
  if (m == Model::Full) {  // everything on: spin, swept, sleeps when it can
    def.lock_rotation = false;
    def.fast = true;
    def.allow_sleep = true;
  }
  return def;
}

rp::BodyDef projectile_def(Model m, const rp::Vec3& p, const rp::Vec3& v) {
  rp::BodyDef def = profiles::projectile(p, v);
  if (m == Model::Full) {
    def.lock_rotation = false;
    def.filter.mask = 0xFFFFFFFFu;  // projectiles also hit each other
  }
  return def;
}

Arena build(Model m) {
  Arena a{
      rp::World::create(m == Model::Full ? profiles::physics_props() : profiles::arena_players())
          .value(),
      {},
      {}};
  rp::World& w = a.world;
  (void)w.add_plane({.normal = rp::Vec3::UnitY(), .offset = 0});
  const rp::Real h = kHalfWidth;
  for (int side = 0; side < 4; ++side) {  // four 1 m thick, 4 m high walls
    const rp::Real s = side % 2 == 0 ? rp::Real(1) : rp::Real(-1);
    const rp::Vec3 center = side < 2 ? rp::Vec3(s * (h + rp::Real(0.5)), 2, 0)
                                     : rp::Vec3(0, 2, s * (h + rp::Real(0.5)));
    const rp::Vec3 half = side < 2 ? rp::Vec3(rp::Real(0.5), 2, h + 1) : rp::Vec3(h + 1, 2, 0.5);
    (void)w.add_box({.center = center, .half_extents = half});
  }
  for (int i = 0; i < 9; ++i) {  // pillars on a 3×3 grid
    const rp::Vec3 c((i % 3 - 1) * rp::Real(10), 2, (i / 3 - 1) * rp::Real(10));
    (void)w.add_box({.center = c, .half_extents = rp::Vec3(1, 2, 1)});
  }
  for (int i = 0; i < kPlayers; ++i) {
    const rp::Vec3 p((i % 8 - rp::Real(3.5)) * 4 + 2, rp::Real(0.4),
                     (i / 8 - rp::Real(3.5)) * 4 + 2);
    a.players.push_back(w.create_body(player_def(m, p)).value());
  }
  return a;
}

/// Player i's scripted horizontal velocity at step n: a run whose heading turns slowly.
rp::Vec3 steer(int i, int n) {
  const double heading = 0.7 * i + 0.02 * n * (1 + i % 3);
  return rp::Vec3(static_cast<rp::Real>(kPlayerSpeed * std::cos(heading)), 0,
                  static_cast<rp::Real>(kPlayerSpeed * std::sin(heading)));
}

struct RunResult {
  double ms_per_step = 0;  ///< World::step only
  rp::StepProfile phases;  ///< per-phase ms, averaged over the steps
  int hits = 0;            ///< projectile-player contact begins
  std::vector<rp::Vec3> final_players;
};

RunResult run(Model m, int steps) {
  Arena a = build(m);
  Lcg rng{12345};
  RunResult r;
  double total_ms = 0;
  for (int n = 0; n < steps; ++n) {
    // Game logic: steer players (keep their vertical speed), retire spent projectiles, fire new.
    for (int i = 0; i < kPlayers; ++i) {
      const rp::Vec3 v = a.world.body_state(a.players[i]).value().linear_velocity;
      rp::Vec3 run_velocity = steer(i, n);
      run_velocity.y() = v.y();
      (void)a.world.set_linear_velocity(a.players[i], run_velocity);
    }
    std::erase_if(a.projectiles, [&](rp::BodyId id) {
      const rp::Vec3 p = a.world.body_state(id).value().position;
      const bool spent = std::abs(p.x()) > kHalfWidth || std::abs(p.z()) > kHalfWidth ||
                         p.y() < 0 || p.y() > 10 ||
                         a.world.body_state(id).value().linear_velocity.norm() < 50;
      if (spent) (void)a.world.destroy_body(id);
      return spent;
    });
    while (static_cast<int>(a.projectiles.size()) < kProjectiles) {
      const int shooter = static_cast<int>(rng.next() * kPlayers) % kPlayers;
      const double yaw = rng.next() * 6.283185307179586, pitch = (rng.next() - 0.5) * 0.1;
      const rp::Vec3 dir(static_cast<rp::Real>(std::cos(yaw) * std::cos(pitch)),
                         static_cast<rp::Real>(std::sin(pitch)),
                         static_cast<rp::Real>(std::sin(yaw) * std::cos(pitch)));
      const rp::Vec3 muzzle = a.world.body_state(a.players[shooter]).value().position +
                              dir * rp::Real(0.6) + rp::Vec3(0, rp::Real(0.3), 0);
      a.projectiles.push_back(
          a.world.create_body(projectile_def(m, muzzle, dir * kProjectileSpeed)).value());
    }
    const auto t0 = std::chrono::steady_clock::now();
    (void)a.world.step(rp::Real(1) / 60);
    total_ms +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const rp::StepProfile& p = a.world.profile();
    r.phases.broad_phase_ms += p.broad_phase_ms / steps;
    r.phases.narrow_phase_ms += p.narrow_phase_ms / steps;
    r.phases.solve_ms += p.solve_ms / steps;
    r.phases.integrate_ms += p.integrate_ms / steps;
    r.phases.continuous_ms += p.continuous_ms / steps;
    r.phases.sleep_ms += p.sleep_ms / steps;
    r.phases.events_ms += p.events_ms / steps;
    for (const rp::ContactBeginEvent& e : a.world.contact_begin_events()) {
      const auto is_player = [&](rp::BodyId id) {
        return std::find(a.players.begin(), a.players.end(), id) != a.players.end();
      };
      const auto is_projectile = [&](rp::BodyId id) {
        return std::find(a.projectiles.begin(), a.projectiles.end(), id) != a.projectiles.end();
      };
      const rp::BodyId other = e.other.body;
      if ((is_player(e.body) && is_projectile(other)) ||
          (is_projectile(e.body) && is_player(other))) {
        ++r.hits;
      }
    }
  }
  r.ms_per_step = total_ms / steps;
  for (const rp::BodyId id : a.players)
    r.final_players.push_back(a.world.body_state(id).value().position);
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Arena bench: the arena_players profile against the full model, same inputs");
  int steps = 600, repeat = 3;
  app.add_option("--steps", steps, "steps per run")->check(CLI::Range(1, 1000000));
  app.add_option("--repeat", repeat, "runs per model; the median ms/step is kept")
      ->check(CLI::Range(1, 100));
  CLI11_PARSE(app, argc, argv);

  RunResult result[2];
  for (const Model m : {Model::Full, Model::ArenaPlayers}) {
    std::vector<RunResult> runs;
    for (int k = 0; k < repeat; ++k) runs.push_back(run(m, steps));
    std::sort(runs.begin(), runs.end(),
              [](const RunResult& x, const RunResult& y) { return x.ms_per_step < y.ms_per_step; });
    result[static_cast<int>(m)] = runs[runs.size() / 2];
    const RunResult& r = result[static_cast<int>(m)];
    std::printf(
        "{\"bench\":\"arena\",\"model\":\"%s\",\"players\":%d,\"projectiles\":%d,\"steps\":%d,"
        "\"ms_per_step\":%.5f,\"projectile_hits\":%d,\"profile\":{\"broad_phase_ms\":%.4f,"
        "\"narrow_phase_ms\":%.4f,\"solve_ms\":%.4f,\"integrate_ms\":%.4f,\"continuous_ms\":%.4f,"
        "\"sleep_ms\":%.4f,\"events_ms\":%.4f}}\n",
        model_name(m), kPlayers, kProjectiles, steps, r.ms_per_step, r.hits,
        r.phases.broad_phase_ms, r.phases.narrow_phase_ms, r.phases.solve_ms, r.phases.integrate_ms,
        r.phases.continuous_ms, r.phases.sleep_ms, r.phases.events_ms);
  }
  const RunResult& full = result[0];
  const RunResult& lean = result[1];
  double mean_dev = 0, max_dev = 0;
  for (int i = 0; i < kPlayers; ++i) {
    const double d = static_cast<double>((full.final_players[i] - lean.final_players[i]).norm());
    mean_dev += d / kPlayers;
    max_dev = std::max(max_dev, d);
  }
  std::printf(
      "{\"bench\":\"arena\",\"summary\":true,\"full_over_profile_cost\":%.3f,"
      "\"player_deviation_mean_m\":%.4f,\"player_deviation_max_m\":%.4f,"
      "\"hits_full\":%d,\"hits_profile\":%d}\n",
      full.ms_per_step / lean.ms_per_step, mean_dev, max_dev, full.hits, lean.hits);
  return 0;
}
