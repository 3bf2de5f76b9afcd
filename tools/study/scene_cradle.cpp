/// Scene 4: Newton's cradle. Touching spheres in a row, no gravity, no friction, e = 1; one or
/// two strikers move at 5 m/s into the row. Exactly elastic pairwise collisions hand all the
/// momentum and energy to the far end: k strikers send off the last k balls at 5 m/s. Racks: 3, 5
/// and 7 balls with one striker, and two striking three. A simultaneous (sequential-impulse)
/// solve of the touching chain spreads them over several balls instead.

#include <algorithm>
#include <cmath>

#include "scenes.h"

namespace ricochet::study {

namespace {

constexpr const char* kScene = "cradle";
constexpr double kRadius = 0.5;    // m
constexpr double kSpeed = 5;       // m/s, well above the 1 m/s restitution threshold
constexpr double kGap = 0.5;       // m between the strikers and the row
constexpr double kRunSeconds = 1;  // impact at 0.1 s

/// balls in all (strikers first), of which strikers move; suffix names its metric.
struct Rack {
  int balls;
  int strikers;
  const char* suffix;
};
/// The first rack is the headline one (its metrics have no suffix).
constexpr Rack kRacks[] = {{5, 1, ""}, {3, 1, "_3"}, {7, 1, "_7"}, {5, 2, "_two"}};

Setting base_setting() {
  return Setting{};
}

struct RackResult {
  std::vector<double> v;  ///< final x velocity per ball
  double energy = 0;      ///< J per kg of one ball
  double deepest = 0;     ///< m
};

RackResult run_rack(const Rack& rack, const Setting& setting, StepClock& clock) {
  rp::WorldDef def = world_def(setting);
  def.gravity = rp::Vec3::Zero();
  rp::World world = create_world(def);
  rp::Material material;
  material.restitution = 1;
  material.friction = 0;
  std::vector<rp::BodyId> balls;
  for (int i = 0; i < rack.balls; ++i) {
    rp::BodyDef body;
    // The row touches, centres 2r apart from 0; the strikers touch each other, kGap before it.
    const bool striker = i < rack.strikers;
    const double x = 2 * kRadius * (i - rack.strikers) - (striker ? kGap : 0.0);
    body.position = rp::Vec3(static_cast<rp::Real>(x), 0, 0);
    body.radius = static_cast<rp::Real>(kRadius);
    body.material = material;
    body.fast = setting.ccd;
    if (striker) body.linear_velocity = rp::Vec3(static_cast<rp::Real>(kSpeed), 0, 0);
    balls.push_back(create_body(world, body));
  }
  RackResult r;
  const long steps = std::lround(kRunSeconds / setting.step_s());
  for (long n = 0; n < steps; ++n) {
    clock.step(world, setting);
    r.deepest = std::max(r.deepest, max_penetration(states_of(world, balls), {}));
  }
  for (const rp::BodyState& s : states_of(world, balls)) {
    r.v.push_back(static_cast<double>(s.linear_velocity.x()));
    r.energy += kinetic_energy(s, 1);
  }
  return r;
}

Outcome run_once(const Setting& setting, StepClock& clock) {
  Outcome out;
  double worst_drift = 0;
  for (const Rack& rack : kRacks) {
    const RackResult r = run_rack(rack, setting, clock);
    const double e0 = 0.5 * kSpeed * kSpeed * rack.strikers;
    double momentum = 0, momentum_last = 0, energy_last = 0;
    std::string velocities;
    for (int i = 0; i < rack.balls; ++i) {
      const double v = r.v[static_cast<std::size_t>(i)];
      momentum += v;
      if (i >= rack.balls - rack.strikers) {
        momentum_last += v;
        energy_last += 0.5 * v * v;
      }
      velocities += format(" %.3f", v / kSpeed);
    }
    const std::string note =
        format("%d balls, %d striking; final v/v0 per ball:%s; total momentum kept %.4f",
               rack.balls, rack.strikers, velocities.c_str(), momentum / (kSpeed * rack.strikers));
    out.metrics.push_back({std::string("momentum_not_in_last") + rack.suffix,
                           1 - momentum_last / (kSpeed * rack.strikers), note});
    out.metrics.push_back(
        {std::string("energy_not_in_last") + rack.suffix, 1 - energy_last / e0, note});
    const double drift = (r.energy - e0) / e0;
    if (std::abs(drift) > std::abs(worst_drift)) worst_drift = drift;
    out.max_penetration = std::max(out.max_penetration, r.deepest);
    if (rack.suffix[0] == '\0' && same_except(setting, base_setting(), kIterations | kCorrection)) {
      const std::string series =
          format("%s %d iterations", correction_name(setting.correction), setting.iterations);
      for (int i = 0; i < rack.balls; ++i)
        out.series.push_back(
            {series, static_cast<double>(i + 1), r.v[static_cast<std::size_t>(i)] / kSpeed});
    }
  }
  out.energy_drift = worst_drift;
  return out;
}

}  // namespace

void run_cradle(Study& study) {
  const Setting base = base_setting();
  SettingList list;
  list.contact_sweeps(study, base);
  list.vary(base, study.dts(), set_dt);
  list.vary(base, study.integrators(), set_integrator);
  list.vary(base, std::vector<bool>{false, true}, set_ccd);
  list.vary(base, std::vector<bool>{true, false}, set_sleep);
  for (const Setting& s : list.settings()) study.measure(kScene, s, run_once);
}

void report_cradle(Report& r) {
  const Results& results = r.results();
  const Setting base = base_setting();
  const auto precisions = r.precisions();
  const std::string& p0 = precisions.at(0);
  r.text(
      "**Reference.** 1 kg spheres (r = 0.5 m) in a row, touching; no gravity, friction 0, "
      "restitution 1 on every ball. The striker starts 0.5 m from the row at 5 m/s. With "
      "pairwise elastic collisions the last ball leaves at 5 m/s and the others stop: 100 % of "
      "the momentum and of the kinetic energy end in the last ball (with two strikers, in the "
      "last two). Racks: 5 balls (the tables below), 3 and 7 balls and two striking three (the "
      "last table). Measured after 1 s. The tables show the **fraction that does NOT reach the "
      "last ball** (0 is ideal); `energy drift` is the change of the total kinetic energy, the "
      "largest of the four racks (0 is ideal), and the note of each row in results.csv lists "
      "every ball's final v/v0. **What to expect.** The row is one simultaneous contact chain, "
      "which the solve treats as inelastic; the restitution pass then replays the step's "
      "impacts as a sequence of pairwise collisions (Guendelman, Bridson and Fedkiw 2003), so "
      "the outcome should be the pairwise answer at every iteration count.");
  r.text("Energy fraction NOT in the last ball, iterations × position correction (" + p0 + "):");
  r.grid_table(kScene, p0, base, kIterations, kCorrection, "energy_not_in_last",
               [](const ResultRow& row) { return percent(row.error); });
  r.text("Momentum fraction NOT in the last ball (" + p0 + "):");
  r.grid_table(kScene, p0, base, kIterations, kCorrection, "momentum_not_in_last",
               [](const ResultRow& row) { return percent(row.error); });
  r.text("The other racks, energy NOT in the last ball(s), iterations x position correction (" +
         p0 + "): 7 balls, then two striking three:");
  r.grid_table(kScene, p0, base, kIterations, kCorrection, "energy_not_in_last_7",
               [](const ResultRow& row) { return percent(row.error); });
  r.grid_table(kScene, p0, base, kIterations, kCorrection, "energy_not_in_last_two",
               [](const ResultRow& row) { return percent(row.error); });
  r.text("Other knobs, one at a time:");
  r.knob_table(kScene, base, {kSubsteps, kDt, kIntegrator, kCcd, kSleep},
               {{"energy not in last", "energy_not_in_last",
                 [](const ResultRow& row) { return percent(row.error); }},
                {"momentum not in last", "momentum_not_in_last",
                 [](const ResultRow& row) { return percent(row.error); }},
                {"total KE drift", "energy_not_in_last",
                 [](const ResultRow& row) { return num(row.energy_drift); }},
                {"ms/step", "energy_not_in_last", ms_cell}});
  // Energy created anywhere in the sweep is worth a sentence of its own.
  const ResultRow* most = nullptr;
  for (const std::string& p : precisions) {
    for (const ResultRow& row : results.rows()) {
      if (row.scene == kScene && row.precision == p && row.metric == "energy_not_in_last" &&
          (!most || row.energy_drift > most->energy_drift)) {
        most = &row;
      }
    }
  }
  if (most && most->energy_drift > 0.01) {
    r.text(
        format("**Energy is created** in some settings: at %d iteration%s, %s, %s, dt %s "
               "(%s) the balls end with %.3g× the initial kinetic energy (%s). With e = 1 "
               "no setting should exceed 1×.",
               most->setting.iterations, most->setting.iterations == 1 ? "" : "s",
               correction_name(most->setting.correction), integrator_name(most->setting.integrator),
               dt_label(most->setting.dt).c_str(), most->precision.c_str(), 1 + most->energy_drift,
               most->note.c_str()));
  }
  const ResultRow* e = results.find(kScene, p0, base, "energy_not_in_last");
  const ResultRow* m = results.find(kScene, p0, base, "momentum_not_in_last");
  if (e && m) {
    r.headline(kScene, format("base setting: last ball gets %s of the momentum and %s of the "
                              "energy (ideal 100 %%); total KE drift %s",
                              percent(1 - m->error).c_str(), percent(1 - e->error).c_str(),
                              num(e->energy_drift).c_str()));
  }

  Plot plot;
  plot.name = "cradle_energy_vs_iterations";
  plot.title = "Cradle: kinetic energy fraction reaching the last ball vs iterations";
  plot.xlabel = "solver iterations";
  plot.ylabel = "KE of last ball / initial KE";
  plot.logx = true;
  plot.commands = {"set yrange [0:1.05]"};
  plot.curves = r.curves(
      kScene, "energy_not_in_last", base, kCorrection, kIterations,
      [](const ResultRow& row) { return static_cast<double>(row.setting.iterations); },
      [](const ResultRow& row) { return 1 - row.error; });
  r.plot(plot);

  Plot balls;
  balls.name = "cradle_final_velocities";
  balls.title = "Cradle: final velocity of each ball / v0 (Baumgarte, " + p0 + ")";
  balls.xlabel = "ball (1 = struck first)";
  balls.ylabel = "v / v0 after 1 s";
  balls.commands = {"set xtics 1", "set xrange [0.5:5.5]"};
  for (const std::string& name : results.series_names(kScene)) {
    if (name.rfind("Baumgarte", 0) != 0) continue;
    balls.curves.push_back(r.series_curve(kScene, p0, name, name, "linespoints"));
  }
  r.plot(balls);
}

}  // namespace ricochet::study
