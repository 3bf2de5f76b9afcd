/// Query bench: world queries in the arena scene (arena_scene.h, arena_players profile, 64 players,
/// 256 bullets, the 20 000-triangle heightfield floor), after a warm-up of --steps steps.
///
/// Rays start at the players' eyes (0.3 m above their centres) in random horizontal to slightly
/// downward directions, 100 m long, ignoring the shooter. Timed, in µs per query (the median of
/// --repeat passes over --rays queries):
///
///   ray_cast_closest    the closest hit among static shapes and bodies
///   ray_cast_spheres    lag compensation: static shapes plus the 64 players as spheres where they
///                       were 100 ms (6 steps) earlier, live bodies left out
///   sphere_cast         the same paths swept by a 0.1 m sphere
///   overlap_sphere      2 m spheres around the players' eyes, bodies only
///   query_grid_rebuild  what the first query after a step pays for rebuilding the query grid
///                       (the first of two identical overlaps minus the second, over 60 steps)
///
/// Prints one JSON line per query kind; the median and the fastest pass are both given, as the
/// fastest is the steadier figure on a shared machine.
///
///   query-bench [--steps 120] [--rays 20000] [--repeat 5] [--label NAME]

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "arena_scene.h"

namespace rp = ricochet::physics;
namespace bench = ricochet::bench;

namespace {

constexpr rp::Real kEyeHeight = rp::Real(0.3);   ///< m above a player's centre
constexpr rp::Real kMaxDistance = 100;           ///< m
constexpr rp::Real kCastRadius = rp::Real(0.1);  ///< m, sphere_cast
constexpr rp::Real kBlastRadius = 2;             ///< m, overlap_sphere

struct Shot {
  rp::BodyId shooter;
  rp::Vec3 origin;     ///< m
  rp::Vec3 direction;  ///< unit
};

constexpr int kRewindSteps = 6;  ///< 100 ms at 60 Hz
constexpr int kRebuildSamples = 60;

/// The arena's players: in the arena_players model every body is a player.
std::vector<rp::BodyId> players_of(const rp::World& world) {
  std::vector<rp::BodyId> players(world.body_count());
  players.resize(world.live_bodies(players));
  return players;
}

std::vector<Shot> make_shots(const rp::World& world, const std::vector<rp::BodyId>& players,
                             int count) {
  std::mt19937_64 engine{777};  // its output is fixed by the standard, unlike its distributions
  const auto uniform = [&] { return static_cast<double>(engine() >> 11) * 0x1.0p-53; };
  std::vector<Shot> shots;
  for (int k = 0; k < count; ++k) {
    const rp::BodyId shooter = players[static_cast<std::size_t>(k) % players.size()];
    const double yaw = uniform() * 6.283185307179586, pitch = -uniform() * 0.15;
    const rp::Vec3 dir(static_cast<rp::Real>(std::cos(yaw) * std::cos(pitch)),
                       static_cast<rp::Real>(std::sin(pitch)),
                       static_cast<rp::Real>(std::sin(yaw) * std::cos(pitch)));
    const rp::Vec3 eye = world.body_state(shooter).value().position + rp::Vec3(0, kEyeHeight, 0);
    shots.push_back({shooter, eye, dir});
  }
  return shots;
}

struct Timing {
  double median_us = 0, fastest_us = 0;  ///< per query
  int hits = 0;                          ///< queries that returned true (last pass)
};

/// µs per query over `repeat` passes of query(shot) over all shots.
template <class Query>
Timing time_queries(const std::vector<Shot>& shots, int repeat, Query&& query) {
  Timing timing;
  std::vector<double> per_query;
  for (int r = 0; r < repeat; ++r) {
    int found = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (const Shot& s : shots) found += query(s) ? 1 : 0;
    const double us =
        std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
    per_query.push_back(us / static_cast<double>(shots.size()));
    timing.hits = found;
  }
  std::sort(per_query.begin(), per_query.end());
  timing.median_us = per_query[per_query.size() / 2];
  timing.fastest_us = per_query.front();
  return timing;
}

void print(const std::string& label, const char* query, int steps, int queries, const Timing& t) {
  std::printf(
      "{\"bench\":\"query\",\"label\":\"%s\",\"query\":\"%s\",\"players\":%d,\"bullets\":%d,"
      "\"mesh_triangles\":%d,\"warmup_steps\":%d,\"queries\":%d,\"us_per_query\":%.4f,"
      "\"fastest_us_per_query\":%.4f,\"hits\":%d}\n",
      label.c_str(), query, bench::kArenaPlayers, bench::kArenaBullets, bench::kArenaMeshTriangles,
      steps, queries, t.median_us, t.fastest_us, t.hits);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Query bench: ray casts, sphere casts and overlaps in the arena scene");
  int steps = 120, rays = 20000, repeat = 5;
  std::string label = "current";
  app.add_option("--steps", steps, "warm-up steps before querying")
      ->check(CLI::Range(kRewindSteps + 1, 100000));
  app.add_option("--rays", rays, "queries per pass")->check(CLI::Range(1, 10000000));
  app.add_option("--repeat", repeat, "passes; the median is kept")->check(CLI::Range(1, 100));
  app.add_option("--label", label, "written into every JSON line");
  CLI11_PARSE(app, argc, argv);

  int step = 0;
  std::vector<std::vector<rp::Vec3>> history;  ///< player positions after each step
  std::vector<double> rebuild_us;
  const bench::ArenaStep query_after_warmup = [&](rp::World& world) {
    (void)world.step(rp::Real(1) / 60);
    ++step;
    const std::vector<rp::BodyId> players = players_of(world);
    std::vector<rp::Vec3> positions(players.size());
    (void)world.read_bodies(players, {.positions = positions});
    history.push_back(std::move(positions));
    if (step >
        steps) {  // after the timed queries: the grid rebuild a step leaves to the next query
      rp::QueryFilter filter;
      filter.statics = false;
      const auto t0 = std::chrono::steady_clock::now();
      (void)world.overlap_sphere(rp::Vec3(0, 1, 0), rp::Real(0.01), filter);
      const auto t1 = std::chrono::steady_clock::now();
      (void)world.overlap_sphere(rp::Vec3(0, 1, 0), rp::Real(0.01), filter);
      const auto t2 = std::chrono::steady_clock::now();
      rebuild_us.push_back(
          std::chrono::duration<double, std::micro>((t1 - t0) - (t2 - t1)).count());
    }
    if (step != steps) return 0.0;
    const std::vector<Shot> shots = make_shots(world, players, rays);
    print(label, "ray_cast_closest", steps, rays, time_queries(shots, repeat, [&](const Shot& s) {
            rp::QueryFilter filter;
            filter.ignore = s.shooter;
            rp::RayHit hit;
            return world.ray_cast_closest(s.origin, s.direction, kMaxDistance, filter, hit);
          }));
    const std::vector<rp::Vec3>& past = history[history.size() - 1 - kRewindSteps];
    std::vector<rp::SphereProxy> proxies;
    for (std::size_t i = 0; i < players.size(); ++i)
      proxies.push_back({past[i], world.body_state(players[i]).value().radius, players[i], i});
    print(label, "ray_cast_spheres", steps, rays, time_queries(shots, repeat, [&](const Shot& s) {
            rp::QueryFilter filter;
            filter.ignore = s.shooter;
            filter.bodies = false;
            rp::RayHit hit;
            return world.ray_cast_spheres(s.origin, s.direction, kMaxDistance, filter, proxies,
                                          hit);
          }));
    print(label, "sphere_cast", steps, rays, time_queries(shots, repeat, [&](const Shot& s) {
            rp::QueryFilter filter;
            filter.ignore = s.shooter;
            rp::RayHit hit;
            return world.sphere_cast(s.origin, kCastRadius, s.direction, kMaxDistance, filter, hit);
          }));
    print(label, "overlap_sphere", steps, rays, time_queries(shots, repeat, [&](const Shot& s) {
            rp::QueryFilter filter;
            filter.statics = false;
            return world.overlap_sphere(s.origin, kBlastRadius, filter).size() > 1;
          }));
    return 0.0;
  };
  (void)bench::run_arena(bench::ArenaModel::ArenaPlayers, steps + kRebuildSamples,
                         query_after_warmup, bench::ArenaFloor::Mesh);
  std::sort(rebuild_us.begin(), rebuild_us.end());
  std::printf(
      "{\"bench\":\"query\",\"label\":\"%s\",\"query\":\"query_grid_rebuild\",\"players\":%d,"
      "\"samples\":%d,\"median_us\":%.4f,\"fastest_us\":%.4f}\n",
      label.c_str(), bench::kArenaPlayers, kRebuildSamples, rebuild_us[rebuild_us.size() / 2],
      rebuild_us.front());
  return 0;
}
