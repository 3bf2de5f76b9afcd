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
/// Prints one JSON line per query kind; the median (nearest rank: the lower middle of an even
/// count) and the fastest pass are both given, as the fastest is the steadier figure on a shared
/// machine.
///
///   query-bench [--steps 120] [--rays 20000] [--repeat 5] [--label NAME] [--out FILE]

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "arena_scene.h"
#include "harness.h"

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
    const bench::Stopwatch pass;
    for (const Shot& s : shots) found += query(s) ? 1 : 0;
    per_query.push_back(pass.elapsed_us() / static_cast<double>(shots.size()));
    timing.hits = found;
  }
  const ricochet::stats::Summary summary = ricochet::stats::summarize(per_query);
  timing.median_us = summary.p50;
  timing.fastest_us = summary.min;
  return timing;
}

bench::JsonObject result(const std::string& label, const char* query, int steps, int queries,
                         const Timing& t) {
  return bench::result_line("query")
      .text("label", label)
      .text("query", query)
      .integer("players", bench::kArenaPlayers)
      .integer("bullets", bench::kArenaBullets)
      .integer("mesh_triangles", bench::kArenaMeshTriangles)
      .integer("warmup_steps", steps)
      .integer("queries", queries)
      .number("us_per_query", t.median_us, 4)
      .number("fastest_us_per_query", t.fastest_us, 4)
      .integer("hits", t.hits);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Query bench: ray casts, sphere casts and overlaps in the arena scene");
  int steps = 120, rays = 20000, repeat = 5;
  std::string label = "current", out;
  app.add_option("--steps", steps, "warm-up steps before querying")
      ->check(CLI::Range(kRewindSteps + 1, 100000));
  app.add_option("--rays", rays, "queries per pass")->check(CLI::Range(1, 10000000));
  app.add_option("--repeat", repeat, "passes; the median is kept")->check(CLI::Range(1, 100));
  app.add_option("--label", label, "written into every JSON line");
  app.add_option("--out", out, "also append the JSON lines to this file");
  CLI11_PARSE(app, argc, argv);
  bench::ResultsOut results(out);
  if (!results.ok()) {
    std::fprintf(stderr, "query-bench: cannot write %s\n", out.c_str());
    return 2;
  }

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
      const bench::Stopwatch first;
      (void)world.overlap_sphere(rp::Vec3(0, 1, 0), rp::Real(0.01), filter);
      const double first_us = first.elapsed_us();
      const bench::Stopwatch second;
      (void)world.overlap_sphere(rp::Vec3(0, 1, 0), rp::Real(0.01), filter);
      rebuild_us.push_back(first_us - second.elapsed_us());
    }
    if (step != steps) return 0.0;
    const std::vector<Shot> shots = make_shots(world, players, rays);
    results.write(result(
        label, "ray_cast_closest", steps, rays, time_queries(shots, repeat, [&](const Shot& s) {
          rp::QueryFilter filter;
          filter.ignore = s.shooter;
          rp::RayHit hit;
          return world.ray_cast_closest(s.origin, s.direction, kMaxDistance, filter, hit);
        })));
    const std::vector<rp::Vec3>& past = history[history.size() - 1 - kRewindSteps];
    std::vector<rp::SphereProxy> proxies;
    for (std::size_t i = 0; i < players.size(); ++i)
      proxies.push_back({past[i], world.body_state(players[i]).value().radius, players[i], i});
    results.write(result(
        label, "ray_cast_spheres", steps, rays, time_queries(shots, repeat, [&](const Shot& s) {
          rp::QueryFilter filter;
          filter.ignore = s.shooter;
          filter.bodies = false;
          rp::RayHit hit;
          return world.ray_cast_spheres(s.origin, s.direction, kMaxDistance, filter, proxies, hit);
        })));
    results.write(result(
        label, "sphere_cast", steps, rays, time_queries(shots, repeat, [&](const Shot& s) {
          rp::QueryFilter filter;
          filter.ignore = s.shooter;
          rp::RayHit hit;
          return world.sphere_cast(s.origin, kCastRadius, s.direction, kMaxDistance, filter, hit);
        })));
    results.write(result(label, "overlap_sphere", steps, rays,
                         time_queries(shots, repeat, [&](const Shot& s) {
                           rp::QueryFilter filter;
                           filter.statics = false;
                           return world.overlap_sphere(s.origin, kBlastRadius, filter).size() > 1;
                         })));
    return 0.0;
  };
  (void)bench::run_arena(bench::ArenaModel::ArenaPlayers, steps + kRebuildSamples,
                         query_after_warmup, bench::ArenaFloor::Mesh);
  const ricochet::stats::Summary rebuild = ricochet::stats::summarize(rebuild_us);
  results.write(bench::result_line("query")
                    .text("label", label)
                    .text("query", "query_grid_rebuild")
                    .integer("players", bench::kArenaPlayers)
                    .integer("samples", kRebuildSamples)
                    .number("median_us", rebuild.p50, 4)
                    .number("fastest_us", rebuild.min, 4));
  return 0;
}
