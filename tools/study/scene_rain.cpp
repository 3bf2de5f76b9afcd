/// Scene 7: the cost axis. The rain scene of tools/bench (rain_scene.h: the exact layout and
/// scoring every engine's bench uses): ms/step against iterations and substeps per position
/// correction, with the penetration each buys.

#include <algorithm>
#include <cmath>

#include "rain_scene.h"
#include "scenes.h"

namespace ricochet::study {

namespace {

constexpr const char* kScene = "rain";
constexpr int kPenetrationEvery = 10;  // steps between penetration samples

Setting base_setting() {
  Setting s;
  s.sleep = false;  // as physics-bench runs it
  return s;
}

void positions_and_velocities(const rp::World& world, const std::vector<rp::BodyId>& ids,
                              std::vector<double>& positions, std::vector<double>& velocities) {
  positions.clear();
  velocities.clear();
  for (const rp::BodyId id : ids) {
    const rp::BodyState s = state_of(world, id);
    for (int k = 0; k < 3; ++k) {
      positions.push_back(static_cast<double>(s.position[k]));
      velocities.push_back(static_cast<double>(s.linear_velocity[k]));
    }
  }
}

Outcome run_once(int bodies, int steps, const Setting& setting, StepClock& clock) {
  const bench::RainScene scene = bench::make_rain_scene(bodies);
  rp::WorldDef def = world_def(setting);
  def.gravity = rp::Vec3(0, static_cast<rp::Real>(scene.gravity), 0);
  rp::World world = create_world(def);
  rp::Material material;
  material.restitution = static_cast<rp::Real>(scene.restitution);
  material.friction = static_cast<rp::Real>(scene.friction);
  const auto plane = [&](const rp::Vec3& normal, double offset) {
    rp::PlaneDef p;
    p.normal = normal;
    p.offset = static_cast<rp::Real>(offset);
    p.material = material;
    add_plane(world, p);
  };
  plane(rp::Vec3::UnitY(), 0);
  plane(rp::Vec3::UnitX(), -scene.wall);
  plane(-rp::Vec3::UnitX(), -scene.wall);
  plane(rp::Vec3::UnitZ(), -scene.wall);
  plane(-rp::Vec3::UnitZ(), -scene.wall);
  std::vector<rp::BodyId> ids;
  for (int i = 0; i < scene.bodies; ++i) {
    const auto p = bench::rain_position(scene, i);
    rp::BodyDef body;
    body.position = rp::Vec3(static_cast<rp::Real>(p[0]), static_cast<rp::Real>(p[1]),
                             static_cast<rp::Real>(p[2]));
    body.radius = static_cast<rp::Real>(scene.radius);
    body.mass = static_cast<rp::Real>(scene.mass);
    body.material = material;
    body.fast = setting.ccd;
    ids.push_back(create_body(world, body));
  }
  std::vector<double> positions, velocities;
  const auto energy = [&] {
    double e = 0;
    for (std::size_t i = 0; i < ids.size(); ++i) {
      const double* v = &velocities[3 * i];
      e += scene.mass *
           (0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) - scene.gravity * positions[3 * i + 1]);
    }
    return e;
  };
  positions_and_velocities(world, ids, positions, velocities);
  const double e0 = energy();
  double deepest = 0;
  bench::RainStats stats;
  for (int n = 1; n <= steps; ++n) {
    clock.step(world, setting);
    if (n % kPenetrationEvery == 0 || n == steps) {
      positions_and_velocities(world, ids, positions, velocities);
      stats = bench::score_rain(scene, positions, velocities);
      deepest = std::max(deepest, stats.max_penetration);
    }
  }
  Outcome out;
  out.metrics.push_back(
      {"max_penetration_m", deepest,
       format("%d spheres; %d steps; penetration sampled every %d steps; at the end: penetration "
              "%.3g m; kinetic energy %.3g J; escaped %d; nan %d",
              bodies, steps, kPenetrationEvery, stats.max_penetration, stats.kinetic_energy,
              stats.escaped, stats.nan)});
  out.energy_drift = (energy() - e0) / std::abs(e0);
  out.max_penetration = deepest;
  return out;
}

}  // namespace

void run_rain(Study& study) {
  const int bodies = study.pick(4096, 1024, 64);
  const int steps = study.pick(600, 300, 30);
  const Setting base = base_setting();
  SettingList list;
  list.contact_sweeps(study, base);
  list.vary(base, std::vector<bool>{false, true}, set_sleep);
  for (const Setting& s : list.settings()) {
    study.measure(kScene, s, [&](const Setting& setting, StepClock& clock) {
      return run_once(bodies, steps, setting, clock);
    });
  }
}

void report_rain(Report& r) {
  const Results& results = r.results();
  const Setting base = base_setting();
  const auto precisions = r.precisions();
  const std::string& p0 = precisions.at(0);
  const ResultRow* b = results.find(kScene, p0, base, "max_penetration_m");
  r.text(
      "**Scene.** The rain scene of `tools/bench` (`rain_scene.h`, identical layout and "
      "scoring): spheres of r = 0.5 m on a jittered grid fall into a box of five planes, "
      "restitution 0.2, friction 0.5, dt 1/60, sleep off as the bench runs it" +
      (b ? " — this run: " + b->note.substr(0, b->note.find("; penetration")) : std::string()) +
      ". It gives the cost axis a realistic scale: ms per step of a pile with thousands of "
      "contacts. **Error:** the deepest overlap (sphere–sphere or sphere–plane), sampled every 10 "
      "steps. **What to expect.** Cost grows about linearly in iterations × substeps (the "
      "solver dominates the step); penetration falls until it reaches the slop (5 mm) that "
      "position correction deliberately leaves.");
  r.text("ms/step, iterations × position correction (" + p0 + "):");
  r.grid_table(kScene, p0, base, kIterations, kCorrection, "max_penetration_m", ms_cell);
  r.text("Max penetration (m), iterations × position correction (" + p0 + "):");
  r.grid_table(kScene, p0, base, kIterations, kCorrection, "max_penetration_m", error_cell());
  r.text("Substeps × position correction, ms/step and max penetration (" + p0 + "):");
  r.grid_table(
      kScene, p0, base, kSubsteps, kCorrection, "max_penetration_m",
      [](const ResultRow& row) { return num(row.ms_per_step) + " ms, " + num(row.error) + " m"; });
  r.text("Sleep on and off at the base setting:");
  r.knob_table(kScene, base, {kSleep},
               {{"ms/step", "max_penetration_m", ms_cell},
                {"max penetration, m", "max_penetration_m", error_cell()}});
  if (b) {
    std::string text =
        format("base (10 iterations, Baumgarte, %s): %s ms/step, max penetration %s m", p0.c_str(),
               num(b->ms_per_step).c_str(), num(b->error).c_str());
    Setting many = base;
    many.iterations = 50;
    if (const ResultRow* m = results.find(kScene, p0, many, "max_penetration_m"))
      text += format("; 50 iterations: %s ms/step, %s m", num(m->ms_per_step).c_str(),
                     num(m->error).c_str());
    r.headline(kScene, text);
  }

  Plot plot;
  plot.name = "rain_penetration_vs_cost";
  plot.title = "Rain: max penetration vs ms/step, iterations 1..50 per position correction";
  plot.xlabel = "ms per step";
  plot.ylabel = "max penetration, m";
  plot.logx = plot.logy = true;
  plot.curves = r.curves(
      kScene, "max_penetration_m", base, kCorrection, kIterations,
      [](const ResultRow& row) { return row.ms_per_step; },
      [](const ResultRow& row) { return row.error; });
  r.plot(plot);

  Plot cost;
  cost.name = "rain_cost_vs_iterations";
  cost.title = "Rain: ms/step vs iterations (solid) and substeps (points) per position correction";
  cost.xlabel = "iterations (x substeps for the substep sweep at 10 iterations)";
  cost.ylabel = "ms per step";
  cost.logx = cost.logy = true;
  cost.curves = r.curves(
      kScene, "max_penetration_m", base, kCorrection, kIterations,
      [](const ResultRow& row) { return static_cast<double>(row.setting.iterations); },
      [](const ResultRow& row) { return row.ms_per_step; });
  for (Curve c : r.curves(
           kScene, "max_penetration_m", base, kCorrection, kSubsteps,
           [](const ResultRow& row) {
             return static_cast<double>(row.setting.iterations * row.setting.substeps);
           },
           [](const ResultRow& row) { return row.ms_per_step; })) {
    c.title += " substeps";
    c.style = "points pointsize 1.5";
    cost.curves.push_back(std::move(c));
  }
  r.plot(cost);
}

}  // namespace ricochet::study
