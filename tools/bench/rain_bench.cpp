/// physics-bench: the rain scene in Ricochet's physics. Prints one JSON line (see rain_scene.h);
/// with --progress also a progress line on stderr and a statistics summary.

#include <chrono>
#include <cstdio>
#include <string>

#include "rain_scene.h"
#include "ricochet/physics/world.h"

namespace rp = ricochet::physics;
using ricochet::bench::RainOptions;

namespace {
const char* correction_name(rp::PositionCorrection c) {
  switch (c) {
    case rp::PositionCorrection::Baumgarte:
      return "baumgarte";
    case rp::PositionCorrection::SplitImpulse:
      return "split";
    case rp::PositionCorrection::SoftStep:
      return "soft";
  }
  return "?";
}
}  // namespace

int main(int argc, char** argv) {
  RainOptions options;
  rp::WorldDef def;
  std::string correction = "default";
  int exit_code = 0;
  const auto add_engine_options = [&](CLI::App& app) {
    app.add_option("--position-correction", correction,
                   "baumgarte, split or soft (default: the WorldDef default)")
        ->check(CLI::IsMember({"default", "baumgarte", "split", "soft"}));
    app.add_option("--substeps", def.substeps, "solver substeps")->check(CLI::Range(1, 64));
    app.add_option("--relax-iterations", def.relax_iterations, "unbiased iterations per substep")
        ->check(CLI::Range(0, 1000));
    app.add_option("--shock-propagation", def.shock_propagation,
                   "1: a last ground-up pass with supports immovable (default); 0: off");
    app.add_option("--wide-simd", def.wide_simd,
                   "1: AVX2 contact solver when the CPU has it; 0: the baseline SSE2 path");
  };
  if (!ricochet::bench::parse_rain_options(argc, argv, "ricochet", options, exit_code,
                                           add_engine_options)) {
    return exit_code;
  }
  if (correction == "baumgarte") def.position_correction = rp::PositionCorrection::Baumgarte;
  if (correction == "split") def.position_correction = rp::PositionCorrection::SplitImpulse;
  if (correction == "soft") def.position_correction = rp::PositionCorrection::SoftStep;

  const ricochet::bench::RainScene scene = ricochet::bench::make_rain_scene(options.bodies);
  def.iterations = options.iterations;
  def.enable_sleep = options.sleep != 0;
  def.contact_events = false;
  auto created = rp::World::create(def);
  if (!created) {
    std::fprintf(stderr, "physics-bench: %s\n", created.error().message.c_str());
    return 2;
  }
  rp::World& world = created.value();

  rp::Material material;
  material.restitution = static_cast<rp::Real>(scene.restitution);
  material.friction = static_cast<rp::Real>(scene.friction);
  const auto add_plane = [&](rp::Vec3 normal, double offset) {
    rp::PlaneDef plane;
    plane.normal = normal;
    plane.offset = static_cast<rp::Real>(offset);
    plane.material = material;
    return world.add_plane(plane).ok();
  };
  const bool planes_ok =
      add_plane(rp::Vec3::UnitY(), 0) && add_plane(rp::Vec3::UnitX(), -scene.wall) &&
      add_plane(-rp::Vec3::UnitX(), -scene.wall) && add_plane(rp::Vec3::UnitZ(), -scene.wall) &&
      add_plane(-rp::Vec3::UnitZ(), -scene.wall);
  if (!planes_ok) {
    std::fprintf(stderr, "physics-bench: could not add the arena planes\n");
    return 2;
  }
  std::vector<rp::BodyId> ids;
  ids.reserve(static_cast<std::size_t>(scene.bodies));
  for (int i = 0; i < scene.bodies; ++i) {
    const auto p = ricochet::bench::rain_position(scene, i);
    rp::BodyDef body;
    body.position = rp::Vec3(static_cast<rp::Real>(p[0]), static_cast<rp::Real>(p[1]),
                             static_cast<rp::Real>(p[2]));
    body.radius = static_cast<rp::Real>(scene.radius);
    body.mass = static_cast<rp::Real>(scene.mass);
    body.material = material;
    auto id = world.create_body(body);
    if (!id) {
      std::fprintf(stderr, "physics-bench: %s\n", id.error().message.c_str());
      return 2;
    }
    ids.push_back(id.value());
  }

  rp::StepProfile sum;
  const auto start = std::chrono::steady_clock::now();
  for (int step = 0; step < options.steps; ++step) {
    if (!world.step(static_cast<rp::Real>(options.dt))) return 2;
    const rp::StepProfile& p = world.profile();
    sum.broad_phase_ms += p.broad_phase_ms;
    sum.narrow_phase_ms += p.narrow_phase_ms;
    sum.solve_ms += p.solve_ms;
    sum.integrate_ms += p.integrate_ms;
    sum.continuous_ms += p.continuous_ms;
    sum.sleep_ms += p.sleep_ms;
    sum.events_ms += p.events_ms;
    sum.contacts += p.contacts;
    if (options.progress && (step % 30 == 0 || step + 1 == options.steps)) {
      std::fprintf(stderr, "\rstep %d/%d  %.3f ms/step  contacts %d  awake %d   ", step + 1,
                   options.steps, p.total_ms, p.contacts, p.bodies_awake);
    }
  }
  const double total_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (options.progress) std::fprintf(stderr, "\n");

  std::vector<double> positions, velocities;
  positions.reserve(3 * ids.size());
  velocities.reserve(3 * ids.size());
  for (const rp::BodyId id : ids) {
    const rp::BodyState s = world.body_state(id).value();
    for (int k = 0; k < 3; ++k) {
      positions.push_back(static_cast<double>(s.position[k]));
      velocities.push_back(static_cast<double>(s.linear_velocity[k]));
    }
  }
  const double n = options.steps;
  char profile[512];
  std::snprintf(
      profile, sizeof profile,
      "{\"broad_phase_ms\":%.4f,\"narrow_phase_ms\":%.4f,\"solve_ms\":%.4f,\"integrate_ms\":%.4f,"
      "\"continuous_ms\":%.4f,\"sleep_ms\":%.4f,\"events_ms\":%.4f,\"contacts_per_step\":%.1f,"
      "\"real_bits\":%d,\"simd\":\"%s\",\"position_correction\":\"%s\",\"substeps\":%d,\"relax_"
      "iterations\":%d}",
      sum.broad_phase_ms / n, sum.narrow_phase_ms / n, sum.solve_ms / n, sum.integrate_ms / n,
      sum.continuous_ms / n, sum.sleep_ms / n, sum.events_ms / n, sum.contacts / n,
      static_cast<int>(sizeof(rp::Real) * 8), world.profile().wide_simd ? "avx2" : "baseline",
      correction_name(def.position_correction), def.substeps, def.relax_iterations);
  return ricochet::bench::report_rain("ricochet", options, scene, total_ms, positions, velocities,
                                      profile);
}
