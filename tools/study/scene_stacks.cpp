/// Scenes 5a and 5b: resting stacks that should not move. A square pyramid of 30 spheres
/// (layers 4×4, 3×3, 2×2, 1) in a corner of three planes, and a column of 10 spheres in a tube
/// of four planes. Both start exactly at rest, touching; the reference is "stays put".
///
/// Drift: the largest displacement of any sphere from its start during the run. Jitter: the RMS
/// speed over every sphere and step. Measured with sleep off (so the solver is what is seen),
/// except in the sleep rows, which show what sleeping hides and saves.

#include <algorithm>
#include <cmath>

#include "scenes.h"

namespace ricochet::study {

namespace {

constexpr double kRadius = 0.5;  // m

struct Stack {
  std::vector<V3> rest;  ///< sphere centres, m
  std::vector<PlaneGeom> planes;
  rp::Material material;
};

Stack make_pyramid() {
  Stack stack;
  const double r = kRadius;
  for (int layer = 0; layer < 4; ++layer) {
    const int n = 4 - layer;
    // A sphere on four touching ones sits r·√2 higher, centred over their square.
    const double y = r + layer * std::sqrt(2.0) * r;
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j)
        stack.rest.emplace_back(r + layer * r + 2 * r * i, y, r + layer * r + 2 * r * j);
    }
  }
  stack.planes = {{V3::UnitY(), 0}, {V3::UnitX(), 0}, {V3::UnitZ(), 0}};
  stack.material.friction = rp::Real(0.6);
  stack.material.rolling_resistance = rp::Real(0.1);  // without it the open sides roll away
  return stack;
}

Stack make_column() {
  Stack stack;
  const double r = kRadius;
  const double half_width = r + 0.01;  // 1 cm clearance on each side
  for (int i = 0; i < 10; ++i) stack.rest.emplace_back(0, r + 2 * r * i, 0);
  stack.planes = {{V3::UnitY(), 0},
                  {V3::UnitX(), -half_width},
                  {-V3::UnitX(), -half_width},
                  {V3::UnitZ(), -half_width},
                  {-V3::UnitZ(), -half_width}};
  stack.material.friction = rp::Real(0.6);
  return stack;
}

Setting base_setting() {
  Setting s;
  s.sleep = false;
  return s;
}

Outcome run_stack(const Stack& stack, double seconds, const Setting& setting, StepClock& clock) {
  rp::World world = create_world(world_def(setting));
  const double g = -static_cast<double>(world.definition().gravity.y());
  for (const PlaneGeom& plane : stack.planes) {
    rp::PlaneDef def;
    def.normal = to_real(plane.normal);
    def.offset = static_cast<rp::Real>(plane.offset);
    def.material = stack.material;
    add_plane(world, def);
  }
  std::vector<rp::BodyId> ids;
  for (const V3& p : stack.rest) {
    rp::BodyDef def;
    def.position = to_real(p);
    def.radius = static_cast<rp::Real>(kRadius);
    def.material = stack.material;
    def.fast = setting.ccd;
    ids.push_back(create_body(world, def));
  }
  const auto energy = [&](const std::vector<rp::BodyState>& states) {
    double e = 0;
    for (const rp::BodyState& s : states)
      e += kinetic_energy(s, 1) + g * static_cast<double>(s.position.y());
    return e;
  };
  const double e0 = energy(states_of(world, ids));
  double drift = 0, speed2 = 0, deepest = 0;
  const long steps = std::lround(seconds / setting.step_s());
  std::vector<rp::BodyState> states;
  for (long n = 0; n < steps; ++n) {
    clock.step(world, setting);
    states = states_of(world, ids);
    for (std::size_t i = 0; i < states.size(); ++i) {
      drift = std::max(drift, (to_d(states[i].position) - stack.rest[i]).norm());
      speed2 += to_d(states[i].linear_velocity).squaredNorm();
    }
    deepest = std::max(deepest, max_penetration(states, stack.planes));
  }
  const long asleep = std::count_if(states.begin(), states.end(),
                                    [](const rp::BodyState& s) { return s.sleeping; });
  double drift_end = 0;
  for (std::size_t i = 0; i < states.size(); ++i)
    drift_end = std::max(drift_end, (to_d(states[i].position) - stack.rest[i]).norm());
  Outcome out;
  const std::string note =
      format("%.0f s; displacement at the end %.3g m; asleep at the end %ld/%zu", seconds,
             drift_end, asleep, states.size());
  out.metrics.push_back({"drift_m", drift, note});
  out.metrics.push_back({"jitter_rms_speed_m_s",
                         std::sqrt(speed2 / static_cast<double>(steps * states.size())), note});
  out.energy_drift = (energy(states) - e0) / std::abs(e0);
  out.max_penetration = deepest;
  return out;
}

void run_stack_scene(Study& study, const char* scene, const Stack& stack) {
  const double seconds = study.pick(30.0, 10.0, 1.0);
  const Setting base = base_setting();
  SettingList list;
  list.contact_sweeps(study, base);
  list.vary(base, study.dts(), set_dt);
  list.vary(base, study.integrators(), set_integrator);
  list.vary(base, std::vector<bool>{false, true}, set_sleep);
  for (const Setting& s : list.settings()) {
    study.measure(scene, s, [&](const Setting& setting, StepClock& clock) {
      return run_stack(stack, seconds, setting, clock);
    });
  }
}

void report_stack(Report& r, const char* scene, const std::string& reference) {
  const Results& results = r.results();
  const Setting base = base_setting();
  const auto precisions = r.precisions();
  const std::string& p0 = precisions.at(0);
  r.text(reference);
  r.text(
      "**Reference:** the start positions (exact rest, touching). **Drift** = largest "
      "displacement of any sphere from its start during the run; **jitter** = RMS speed over "
      "all spheres and steps (both 0 ideally). The base setting here has **sleep off**, so the "
      "solver itself is measured; the sleep rows show what sleeping hides and what it saves. "
      "**What to expect.** More iterations converge the stack's contact forces (less sag, less "
      "creep); substeps do the same at a higher price but also shorten the step; Baumgarte "
      "pushes penetration out with velocity (can inject jitter), SplitImpulse and SoftStep do "
      "not carry that velocity on; SoftStep is built for substeps ≥ 4 and is soft (sags) "
      "at 1. Explicit Euler adds gravity after moving the bodies, so a resting sphere ends "
      "every step with v = g·h (0.16 m/s at 1/60): its jitter row shows that, not motion.");
  r.text("Drift (m), iterations × position correction (" + p0 + "):");
  r.grid_table(scene, p0, base, kIterations, kCorrection, "drift_m", error_cell());
  r.text("Jitter (RMS speed, m/s), iterations × position correction (" + p0 + "):");
  r.grid_table(scene, p0, base, kIterations, kCorrection, "jitter_rms_speed_m_s", error_cell());
  r.text("Substeps × position correction, drift (m) (" + p0 + "):");
  r.grid_table(scene, p0, base, kSubsteps, kCorrection, "drift_m", error_cell());
  r.text("One knob at a time (cost in ms/step; sleep on is the engine default):");
  r.knob_table(scene, base, {kSleep, kSubsteps, kDt, kIntegrator},
               {{"drift, m", "drift_m", error_cell()},
                {"jitter, m/s", "jitter_rms_speed_m_s", error_cell()},
                {"max penetration, m", "drift_m",
                 [](const ResultRow& row) { return num(row.max_penetration); }},
                {"ms/step", "drift_m", ms_cell}});

  const ResultRow* b = results.find(scene, p0, base, "drift_m");
  const ResultRow* j = results.find(scene, p0, base, "jitter_rms_speed_m_s");
  Setting sleeping = base;
  sleeping.sleep = true;
  const ResultRow* s = results.find(scene, p0, sleeping, "drift_m");
  if (b && j) {
    std::string text =
        format("base (sleep off): drift %s m, jitter %s m/s, %s ms/step", num(b->error).c_str(),
               num(j->error).c_str(), num(b->ms_per_step).c_str());
    if (s)
      text += format("; sleep on: drift %s m, %s ms/step", num(s->error).c_str(),
                     num(s->ms_per_step).c_str());
    r.headline(scene, text);
  }

  Plot plot;
  plot.name = std::string(scene) + "_drift_vs_cost";
  plot.title = std::string(scene) + ": drift vs cost, iterations 1..50 per position correction";
  plot.xlabel = "ms per step";
  plot.ylabel = "max displacement from rest, m";
  plot.logx = plot.logy = true;
  plot.curves = r.curves(
      scene, "drift_m", base, kCorrection, kIterations,
      [](const ResultRow& row) { return row.ms_per_step; },
      [](const ResultRow& row) { return row.error; });
  r.plot(plot);

  Plot jitter = plot;
  jitter.name = std::string(scene) + "_jitter_vs_cost";
  jitter.title = std::string(scene) + ": jitter vs cost, iterations 1..50 per position correction";
  jitter.ylabel = "RMS speed, m/s";
  jitter.curves = r.curves(
      scene, "jitter_rms_speed_m_s", base, kCorrection, kIterations,
      [](const ResultRow& row) { return row.ms_per_step; },
      [](const ResultRow& row) { return row.error; });
  r.plot(jitter);
}

}  // namespace

void run_pyramid(Study& study) {
  run_stack_scene(study, "pyramid", make_pyramid());
}

void run_column(Study& study) {
  run_stack_scene(study, "column", make_column());
}

void report_pyramid(Report& r) {
  report_stack(r, "pyramid",
               "**Scene.** 30 spheres (r = 0.5 m, 1 kg) in a square pyramid of 4 layers "
               "(4×4, 3×3, 2×2, 1; each sphere resting in the hollow of four below) in the corner "
               "of a floor and two walls; friction 0.6 and rolling resistance 0.1 everywhere "
               "(without rolling resistance the two open sides roll away), restitution 0. 30 s "
               "(10 s in quick mode).");
}

void report_column(Report& r) {
  report_stack(r, "column",
               "**Scene.** 10 spheres (r = 0.5 m, 1 kg) stacked vertically in a square tube of "
               "four wall planes with 1 cm clearance, on a floor; friction 0.6, restitution 0. "
               "The bottom contact carries nine spheres' weight. 30 s (10 s in quick mode).");
}

}  // namespace ricochet::study
