/// Scenes 2a and 2b: a sphere on a Hooke spring and a sphere on an eccentric Kepler orbit, both
/// force fields of the world (no gravity, no contacts), for 60 s. The conserved energy is the
/// reference; the closed-form position (cosine, Kepler's equation) gives the phase error too.
///
/// Explicit Euler gains energy every step, semi-implicit Euler (symplectic) keeps it within a
/// bounded band, Rk4 loses a little each step (tiny, but one-signed).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>

#include "scenes.h"

namespace ricochet::study {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kRunSeconds = 60;
constexpr double kSampleSeconds = 0.25;  // series resolution

// Spring: ω = π rad/s (period 2 s), amplitude 1 m, rest length 0, anchor at the origin.
constexpr double kSpringStiffness = kPi * kPi;  // N/m with m = 1 kg
constexpr double kSpringAmplitude = 1;          // m

// Orbit: periapsis 2 m, eccentricity 0.5, period 5 s around a point attractor at the origin.
constexpr double kOrbitEccentricity = 0.5;
constexpr double kOrbitPeriapsis = 2;                                           // m
constexpr double kOrbitSemiMajor = kOrbitPeriapsis / (1 - kOrbitEccentricity);  // m
constexpr double kOrbitPeriod = 5;                                              // s
constexpr double kOrbitStrength = 4 * kPi * kPi * kOrbitSemiMajor * kOrbitSemiMajor *
                                  kOrbitSemiMajor / (kOrbitPeriod * kOrbitPeriod);  // m³/s²

Setting base_setting() {
  return Setting{};
}

/// A world without gravity whose speed clamp cannot hide an explicit-Euler blow-up.
rp::World free_world(const Setting& setting) {
  rp::WorldDef def = world_def(setting);
  def.gravity = rp::Vec3::Zero();
  def.max_linear_speed = rp::Real(1e8);
  return create_world(def);
}

/// Steps a lone body for 60 s and records what both oscillators report: the energy error
/// (worst over the first 6 s, i.e. more than a period of either oscillator, and over the whole
/// run), the final drift, the position error against the closed form at the end, and (at the
/// base dt) |dE/E0| over time. Returns the final state.
rp::BodyState run_and_track(rp::World& world, rp::BodyId ball, const Setting& setting,
                            StepClock& clock,
                            const std::function<double(const rp::BodyState&)>& energy,
                            const std::function<V3(double)>& exact_position, Outcome& out) {
  constexpr double kEarlySeconds = kRunSeconds / 10;
  const double e0 = energy(state_of(world, ball));
  const bool record = same_except(setting, base_setting(), kIntegrator);
  const char* series = integrator_name(setting.integrator);
  double max_early = 0, max_all = 0, next_sample = 0;
  const auto track = [&](double t, const rp::BodyState& s) {
    const double relative = std::abs(energy(s) - e0) / std::abs(e0);
    max_all = std::isfinite(relative) ? std::max(max_all, relative) : relative;
    if (t <= kEarlySeconds) max_early = max_all;
    if (record && t >= next_sample - 1e-9) {
      out.series.push_back({series, t, relative});
      next_sample += kSampleSeconds;
    }
  };
  const double h = setting.step_s();
  const long steps = std::lround(kRunSeconds / h);
  rp::BodyState s = state_of(world, ball);
  track(0, s);
  for (long n = 1; n <= steps; ++n) {
    clock.step(world, setting);
    s = state_of(world, ball);
    track(static_cast<double>(n) * h, s);
  }
  const double t = static_cast<double>(steps) * h;
  out.energy_drift = (energy(s) - e0) / std::abs(e0);
  out.metrics.push_back({"max_rel_energy_error", max_all,
                         format("max |dE/E0| first %.0f s: %.3g; whole run: %.3g", kEarlySeconds,
                                max_early, max_all)});
  out.metrics.push_back({"pos_error_60s_m", (to_d(s.position) - exact_position(t)).norm(), {}});
  return s;
}

Outcome run_spring_once(const Setting& setting, StepClock& clock) {
  rp::World world = free_world(setting);
  rp::BodyDef def;
  def.position = rp::Vec3(static_cast<rp::Real>(kSpringAmplitude), 0, 0);
  def.fast = setting.ccd;
  const rp::BodyId ball = create_body(world, def);
  rp::SpringDef spring;
  spring.body = ball;
  spring.stiffness = static_cast<rp::Real>(kSpringStiffness);
  must(world.add_spring(spring), "add_spring");

  const double k = static_cast<double>(spring.stiffness);
  const double omega = std::sqrt(k);
  Outcome out;
  run_and_track(
      world, ball, setting, clock,
      [&](const rp::BodyState& s) {
        return 0.5 * to_d(s.linear_velocity).squaredNorm() +
               0.5 * k * to_d(s.position).squaredNorm();
      },
      [&](double t) { return V3(kSpringAmplitude * std::cos(omega * t), 0, 0); }, out);
  return out;
}

/// Position on the orbit t seconds after periapsis (periapsis on +x, motion towards +y).
V3 kepler_position(double t, double strength) {
  const double a = kOrbitSemiMajor, e = kOrbitEccentricity;
  const double n = std::sqrt(strength / (a * a * a));
  const double mean = std::fmod(n * t, 2 * kPi);
  double eccentric = mean;
  for (int i = 0; i < 50; ++i)
    eccentric -= (eccentric - e * std::sin(eccentric) - mean) / (1 - e * std::cos(eccentric));
  return V3(a * (std::cos(eccentric) - e), a * std::sqrt(1 - e * e) * std::sin(eccentric), 0);
}

Outcome run_orbit_once(const Setting& setting, StepClock& clock) {
  rp::World world = free_world(setting);
  rp::AttractorDef attractor;
  attractor.strength = static_cast<rp::Real>(kOrbitStrength);
  must(world.add_attractor(attractor), "add_attractor");
  const double gm = static_cast<double>(attractor.strength);
  const double speed_at_periapsis =
      std::sqrt(gm * (2 / kOrbitPeriapsis - 1 / kOrbitSemiMajor));  // vis-viva
  rp::BodyDef def;
  def.position = rp::Vec3(static_cast<rp::Real>(kOrbitPeriapsis), 0, 0);
  def.linear_velocity = rp::Vec3(0, static_cast<rp::Real>(speed_at_periapsis), 0);
  def.fast = setting.ccd;
  const rp::BodyId ball = create_body(world, def);
  const rp::BodyState start = state_of(world, ball);
  const V3 l0 = to_d(start.position).cross(to_d(start.linear_velocity));

  Outcome out;
  const rp::BodyState end = run_and_track(
      world, ball, setting, clock,
      [&](const rp::BodyState& s) {
        return 0.5 * to_d(s.linear_velocity).squaredNorm() - gm / to_d(s.position).norm();
      },
      [&](double t) { return kepler_position(t, gm); }, out);
  const V3 l1 = to_d(end.position).cross(to_d(end.linear_velocity));
  out.note = format("angular momentum drift %.3g", (l1 - l0).norm() / l0.norm());
  return out;
}

void run_oscillator(Study& study, const char* scene,
                    Outcome (*run_once)(const Setting&, StepClock&)) {
  SettingList list;
  list.grid(base_setting(), study.integrators(), set_integrator, study.dts(), set_dt);
  for (const Setting& s : list.settings()) study.measure(scene, s, run_once);
}

/// "bounded" when the whole run's worst energy error stays under 10 % and within twice that of
/// the first 6 s (a symplectic band is reached within a period); otherwise "gains" or "loses" by
/// the sign of the final drift.
std::string trend(const ResultRow& row) {
  double early = 0, whole = 0;
  if (std::sscanf(row.note.c_str(), "max |dE/E0| first %*f s: %lf; whole run: %lf", &early,
                  &whole) != 2) {
    return "?";
  }
  if (!std::isfinite(whole)) return "blows up";
  if (whole <= 2 * early && whole < 0.1) return "bounded";
  return row.energy_drift > 0 ? "gains" : "loses";
}

void report_oscillator(Report& r, const char* scene, const std::string& reference) {
  const Results& results = r.results();
  const Setting base = base_setting();
  const auto precisions = r.precisions();
  r.text(reference);
  r.text(
      "**What to expect.** Explicit Euler multiplies the energy by about (1 + ω²h²) per step: it "
      "grows without bound. Semi-implicit Euler is symplectic: its energy error oscillates in a "
      "band of width ~ωh and does not grow (\"bounded\" below: the worst error over 60 s is "
      "under 10 % and within 2× the worst of the first 6 s, more than one period; otherwise it "
      "\"gains\" or \"loses\"). Rk4 loses ~(ωh)⁶ per step: tiny and one-signed, "
      "until float round-off (~1e-7 per step) dominates. ExactBallistic is exact only for "
      "constant acceleration; with a force field it is a second-order position update on a "
      "first-order velocity update. The world's speed clamp is raised to 1e8 m/s so it cannot "
      "hide a blow-up.");
  std::vector<std::string> header = {"integrator", "dt"};
  for (const std::string& p : precisions) {
    header.push_back("max |ΔE/E0| (" + p + ")");
    header.push_back("final ΔE/E0 (" + p + ")");
    header.push_back("trend (" + p + ")");
    header.push_back("position error 60 s, m (" + p + ")");
  }
  header.push_back("ms per simulated s (" + precisions.at(0) + ")");
  std::vector<std::vector<std::string>> rows;
  for (const ResultRow* row :
       results.select(scene, precisions.at(0), "max_rel_energy_error", base, kIntegrator | kDt)) {
    std::vector<std::string> cells = {integrator_name(row->setting.integrator),
                                      dt_label(row->setting.dt)};
    for (const std::string& p : precisions) {
      const ResultRow* e = results.find(scene, p, row->setting, "max_rel_energy_error");
      const ResultRow* x = results.find(scene, p, row->setting, "pos_error_60s_m");
      cells.push_back(e ? num(e->error) : "—");
      cells.push_back(e ? num(e->energy_drift) : "—");
      cells.push_back(e ? trend(*e) : "—");
      cells.push_back(x ? num(x->error) : "—");
    }
    cells.push_back(num(row->ms_per_sim_s));
    rows.push_back(std::move(cells));
  }
  r.table(header, rows);

  std::string headline;
  for (const rp::Integrator i : {rp::Integrator::ExplicitEuler, rp::Integrator::SemiImplicitEuler,
                                 rp::Integrator::ExactBallistic, rp::Integrator::Rk4}) {
    Setting s = base;
    s.integrator = i;
    const ResultRow* row = results.find(scene, precisions.at(0), s, "max_rel_energy_error");
    if (!row) continue;
    headline += format("%s%s %s (%s)", headline.empty() ? "" : "; ", integrator_name(i),
                       num(row->energy_drift).c_str(), trend(*row).c_str());
  }
  if (!headline.empty())
    r.headline(scene, "final ΔE/E0 after 60 s at 1/60 (" + precisions.at(0) + "): " + headline);

  Plot drift;
  drift.name = std::string(scene) + "_energy_vs_time";
  drift.title = std::string(scene) + ": |E - E0| / |E0| over time at dt 1/60, per integrator";
  drift.xlabel = "t, s";
  drift.ylabel = "|dE / E0|";
  drift.logy = true;
  drift.commands = {"set key outside right top"};
  for (const std::string& p : precisions) {
    for (const std::string& name : results.series_names(scene)) {
      drift.curves.push_back(
          r.series_curve(scene, p, name, precisions.size() > 1 ? name + " " + p : name,
                         p == "double" ? "lines dashtype 2 linewidth 1.5" : "lines linewidth 1.5"));
    }
  }
  r.plot(drift);

  Plot cost;
  cost.name = std::string(scene) + "_error_vs_cost";
  cost.title = std::string(scene) + ": worst energy error over 60 s vs cost (dt 1/30 .. 1/1000)";
  cost.xlabel = "ms of World::step per simulated second";
  cost.ylabel = "max |dE / E0| over 60 s";
  cost.logx = cost.logy = true;
  cost.curves = r.curves(
      scene, "max_rel_energy_error", base, kIntegrator, kDt,
      [](const ResultRow& row) { return row.ms_per_sim_s; },
      [](const ResultRow& row) { return row.error; });
  r.plot(cost);
}

}  // namespace

void run_spring(Study& study) {
  run_oscillator(study, "spring", run_spring_once);
}

void run_orbit(Study& study) {
  run_oscillator(study, "orbit", run_orbit_once);
}

void report_spring(Report& r) {
  report_oscillator(
      r, "spring",
      "**Reference.** A 1 kg sphere on a world spring (`World::add_spring`, k = π² N/m, rest "
      "length 0, no damping) to a fixed anchor, no gravity, released 1 m from the anchor: "
      "ω = π rad/s (period 2 s), energy ½·m·v² + ½·k·x² is conserved, x(t) = cos(ωt) m. Run for "
      "60 s (30 periods).");
}

void report_orbit(Report& r) {
  report_oscillator(
      r, "orbit",
      format("**Reference.** A 1 kg sphere on a Kepler orbit around a point attractor "
             "(`World::add_attractor`, G·M = %.4g m³/s²) with eccentricity 0.5: periapsis 2 m, "
             "apoapsis 6 m, period 5 s; started at periapsis, run for 60 s (12 orbits). Energy "
             "½·v² − G·M/r is conserved; the position is compared with Kepler's equation. The "
             "note gives the angular momentum drift (conserved too).",
             kOrbitStrength));
}

}  // namespace ricochet::study
