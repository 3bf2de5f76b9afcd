#pragma once
/// The rain benchmark scene, shared by Ricochet's bench and the Bullet/ODE peers so every engine
/// runs exactly the same setup and is scored by the same code.
///
/// N spheres (radius 0.5 m, mass 1 kg) on a jittered grid above a floor plane y = 0, inside four
/// wall planes at x, z = ±side·1.1; restitution 0.2, friction 0.5, gravity -9.81 m/s².

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>
#include <unordered_map>
#include <vector>

namespace ricochet::bench {

struct RainOptions {
  int bodies = 4096;
  int steps = 600;
  int iterations = 10;
  double dt = 1.0 / 60.0;
  int sleep = 0;
  std::string dump_positions;
  bool progress = false;
};

/// Parses the common command line. Returns false (after printing help or the error) to exit.
/// `add_engine_options` may add engine-specific options to the parser before parsing.
template <class AddEngineOptions>
bool parse_rain_options(int argc, char** argv, const char* engine, RainOptions& options,
                        int& exit_code, AddEngineOptions&& add_engine_options) {
  CLI::App app{std::string("Rain benchmark scene, engine ") + engine};
  app.add_option("--bodies", options.bodies, "number of spheres")->check(CLI::Range(1, 10'000'000));
  app.add_option("--steps", options.steps, "steps to simulate")->check(CLI::Range(1, 10'000'000));
  app.add_option("--iterations", options.iterations, "solver iterations")
      ->check(CLI::Range(1, 1000));
  app.add_option("--dt", options.dt, "time step in seconds")->check(CLI::Range(1e-6, 1.0));
  app.add_option("--sleep", options.sleep, "allow sleeping (0 or 1)")->check(CLI::Range(0, 1));
  app.add_option("--dump-positions", options.dump_positions,
                 "write final positions, one 'x y z' line per sphere in creation order");
  app.add_flag("--progress", options.progress, "print a progress line to stderr");
  add_engine_options(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    exit_code = app.exit(e);
    return false;
  }
  return true;
}

inline bool parse_rain_options(int argc, char** argv, const char* engine, RainOptions& options,
                               int& exit_code) {
  return parse_rain_options(argc, argv, engine, options, exit_code, [](CLI::App&) {});
}

struct RainScene {
  int bodies = 0;
  int side = 0;
  double radius = 0.5;   ///< m
  double mass = 1.0;     ///< kg
  double spacing = 1.2;  ///< m
  double wall = 0;       ///< m, walls at x, z = ±wall
  double restitution = 0.2;
  double friction = 0.5;
  double gravity = -9.81;  ///< m/s², along y
};

inline RainScene make_rain_scene(int bodies) {
  RainScene scene;
  scene.bodies = bodies;
  scene.side = static_cast<int>(std::ceil(std::cbrt(static_cast<double>(bodies))));
  // cbrt of a perfect cube may round up (cbrt(64) = 4.0000000001); correct by integer check.
  while (scene.side > 1 && (scene.side - 1) * (scene.side - 1) * (scene.side - 1) >= bodies) {
    --scene.side;
  }
  scene.wall = scene.side * 1.1;
  return scene;
}

/// Initial position of sphere i, exactly as the benchmark specifies.
inline std::array<double, 3> rain_position(const RainScene& scene, int i) {
  const int side = scene.side;
  const int x = i % side;
  const int z = (i / side) % side;
  const int y = i / (side * side);
  const double jx =
      0.01 * (static_cast<double>((static_cast<std::int64_t>(i) * 7919) % 13) - 6) / 6;
  const double jz =
      0.01 * (static_cast<double>((static_cast<std::int64_t>(i) * 104729) % 11) - 5) / 5;
  const double s = scene.spacing;
  return {(x - side / 2.0 + 0.5) * s + jx, 1 + y * s, (z - side / 2.0 + 0.5) * s + jz};
}

struct RainStats {
  double kinetic_energy = 0;   ///< J, linear only
  double max_penetration = 0;  ///< m, floor, walls and sphere-sphere
  int escaped = 0;             ///< spheres whose centre left the arena
  int nan = 0;                 ///< spheres with a non-finite position or velocity
};

/// Scores final positions and linear velocities (3 doubles per sphere each).
inline RainStats score_rain(const RainScene& scene, const std::vector<double>& positions,
                            const std::vector<double>& velocities) {
  RainStats stats;
  const int n = scene.bodies;
  const double r = scene.radius;
  std::vector<int> finite;
  finite.reserve(n);
  for (int i = 0; i < n; ++i) {
    const double* p = &positions[3 * i];
    const double* v = &velocities[3 * i];
    bool ok = true;
    for (int k = 0; k < 3; ++k) ok = ok && std::isfinite(p[k]) && std::isfinite(v[k]);
    if (!ok) {
      ++stats.nan;
      continue;
    }
    finite.push_back(i);
    stats.kinetic_energy += 0.5 * scene.mass * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (p[1] < 0 || std::abs(p[0]) > scene.wall || std::abs(p[2]) > scene.wall) ++stats.escaped;
    stats.max_penetration = std::max(stats.max_penetration, r - p[1]);
    stats.max_penetration = std::max(stats.max_penetration, r - (scene.wall - std::abs(p[0])));
    stats.max_penetration = std::max(stats.max_penetration, r - (scene.wall - std::abs(p[2])));
  }
  // Sphere-sphere penetration with a uniform grid of cell 2r: only neighbouring cells can touch.
  const double cell = 2 * r;
  auto key = [](std::int64_t x, std::int64_t y, std::int64_t z) {
    return (x * 73856093) ^ (y * 19349663) ^ (z * 83492791);
  };
  std::unordered_map<std::int64_t, std::vector<int>> grid;
  grid.reserve(finite.size() * 2);
  auto cell_of = [&](int i, int k) {
    return static_cast<std::int64_t>(std::floor(positions[3 * i + k] / cell));
  };
  for (int i : finite) grid[key(cell_of(i, 0), cell_of(i, 1), cell_of(i, 2))].push_back(i);
  for (int i : finite) {
    const std::int64_t cx = cell_of(i, 0), cy = cell_of(i, 1), cz = cell_of(i, 2);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          auto it = grid.find(key(cx + dx, cy + dy, cz + dz));
          if (it == grid.end()) continue;
          for (int j : it->second) {
            if (j <= i) continue;
            double d2 = 0;
            for (int k = 0; k < 3; ++k) {
              const double d = positions[3 * i + k] - positions[3 * j + k];
              d2 += d * d;
            }
            if (d2 < 4 * r * r)
              stats.max_penetration = std::max(stats.max_penetration, 2 * r - std::sqrt(d2));
          }
        }
  }
  stats.max_penetration = std::max(stats.max_penetration, 0.0);
  return stats;
}

inline bool dump_positions(const std::string& path, const std::vector<double>& positions) {
  std::ofstream out(path);
  if (!out) {
    std::fprintf(stderr, "cannot write positions to %s\n", path.c_str());
    return false;
  }
  char line[128];
  for (size_t i = 0; i + 2 < positions.size(); i += 3) {
    std::snprintf(line, sizeof line, "%.6f %.6f %.6f\n", positions[i], positions[i + 1],
                  positions[i + 2]);
    out << line;
  }
  return static_cast<bool>(out);
}

/// Prints the one-line JSON result. profile_json is an object literal ("{}" when none).
inline void print_rain_json(const char* engine, const RainOptions& options, double ms_per_step,
                            const RainStats& stats, const std::string& profile_json) {
  std::printf(
      "{\"engine\":\"%s\",\"scene\":\"rain\",\"bodies\":%d,\"steps\":%d,\"iterations\":%d,"
      "\"dt\":%.9g,\"sleep\":%d,\"ms_per_step\":%.6g,\"kinetic_energy\":%.6g,\"max_penetration\":%."
      "6g,"
      "\"escaped\":%d,\"nan\":%d,\"profile\":%s}\n",
      engine, options.bodies, options.steps, options.iterations, options.dt, options.sleep,
      ms_per_step, stats.kinetic_energy, stats.max_penetration, stats.escaped, stats.nan,
      profile_json.c_str());
  std::fflush(stdout);
}

/// The end of every engine's run: score the final state, print the JSON line, dump positions if
/// asked. Returns the process exit code.
inline int report_rain(const char* engine, const RainOptions& options, const RainScene& scene,
                       double total_ms, const std::vector<double>& positions,
                       const std::vector<double>& velocities, const std::string& profile_json) {
  const RainStats stats = score_rain(scene, positions, velocities);
  print_rain_json(engine, options, total_ms / options.steps, stats, profile_json);
  if (options.progress) {
    std::fprintf(stderr,
                 "rain (%s): %d spheres, %d steps: %.3f ms/step, kinetic energy %.4g J, max "
                 "penetration %.2f mm, "
                 "escaped %d, NaN %d\n",
                 engine, scene.bodies, options.steps, total_ms / options.steps,
                 stats.kinetic_energy, stats.max_penetration * 1000, stats.escaped, stats.nan);
  }
  if (!options.dump_positions.empty() && !dump_positions(options.dump_positions, positions))
    return 1;
  return 0;
}

}  // namespace ricochet::bench
