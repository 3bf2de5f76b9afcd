/// Scenes 6a and 6b: friction turning sliding into rolling. A solid sphere launched sliding
/// (v0, no spin) on a flat floor ends rolling at 5/7·v0 after t_s = 2·v0/(7·μ·g); a solid sphere
/// released on a slope rolls without slipping at a = 5/7·g·sin θ (when μ ≥ 2/7·tan θ).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "scenes.h"

namespace ricochet::study {

namespace {

constexpr double kRadius = 0.5;  // m
// Sliding: v0 and μ give a slip phase of 0.49 s.
constexpr double kSlideSpeed = 5;       // m/s
constexpr double kSlideFriction = 0.3;  // ball and floor: geometric mean 0.3
constexpr double kSlideSeconds = 3;
// Slope: 20°, μ = 0.5 (rolling needs μ ≥ 2/7·tan 20° = 0.104).
constexpr double kSlopeDegrees = 20;
constexpr double kSlopeFriction = 0.5;
constexpr double kSlopeSeconds = 2;

Setting base_setting() {
  return Setting{};
}

/// Speed of the contact point relative to the surface with normal n (m/s).
double slip_speed(const rp::BodyState& s, const V3& n) {
  return (to_d(s.linear_velocity) + to_d(s.angular_velocity).cross(-kRadius * n)).norm();
}

Outcome run_slide_once(const Setting& setting, StepClock& clock) {
  rp::World world = create_world(world_def(setting));
  const double g = -static_cast<double>(world.definition().gravity.y());
  rp::Material material;
  material.friction = static_cast<rp::Real>(kSlideFriction);
  rp::PlaneDef floor;
  floor.material = material;
  add_plane(world, floor);
  rp::BodyDef def;
  def.position = rp::Vec3(0, static_cast<rp::Real>(kRadius), 0);
  def.radius = static_cast<rp::Real>(kRadius);
  def.linear_velocity = rp::Vec3(static_cast<rp::Real>(kSlideSpeed), 0, 0);
  def.material = material;
  def.fast = setting.ccd;
  const rp::BodyId ball = create_body(world, def);

  const double mu = kSlideFriction;
  const double slip_time = 2 * kSlideSpeed / (7 * mu * g);
  const double v_final = 5.0 / 7.0 * kSlideSpeed;
  const auto exact_x = [&](double t) {
    const double ts = std::min(t, slip_time);
    return kSlideSpeed * ts - 0.5 * mu * g * ts * ts + v_final * std::max(0.0, t - slip_time);
  };
  const double e0 = 0.5 * kSlideSpeed * kSlideSpeed;
  const bool record = setting == base_setting();
  Outcome out;
  double measured_slip_time = -1;
  double deepest = 0;
  const double h = setting.step_s();
  const long steps = std::lround(kSlideSeconds / h);
  rp::BodyState s;
  for (long n = 1; n <= steps; ++n) {
    clock.step(world, setting);
    s = state_of(world, ball);
    const double t = static_cast<double>(n) * h;
    deepest = std::max(deepest, kRadius - static_cast<double>(s.position.y()));
    if (measured_slip_time < 0 && slip_speed(s, V3::UnitY()) < 0.01 * kSlideSpeed)
      measured_slip_time = t;
    if (record && t <= 1.5) {
      out.series.push_back({"v", t, static_cast<double>(s.linear_velocity.x())});
      out.series.push_back({"r*omega", t, -kRadius * static_cast<double>(s.angular_velocity.z())});
    }
  }
  const double v = static_cast<double>(s.linear_velocity.x());
  const double t_end = static_cast<double>(steps) * h;
  const std::string note = format(
      "slip ends at %.4g s (predicted 2*v0/(7*mu*g) = %.4g s); final v = %.5g m/s (5/7 v0 = %.5g); "
      "final r*omega/v = %.4f",
      measured_slip_time, slip_time, v, v_final,
      -kRadius * static_cast<double>(s.angular_velocity.z()) / v);
  out.metrics.push_back({"rel_error_final_speed", std::abs(v - v_final) / v_final, note});
  out.metrics.push_back(
      {"pos_error_3s_m", std::abs(static_cast<double>(s.position.x()) - exact_x(t_end)), note});
  out.energy_drift = (kinetic_energy(s, 1) - e0) / e0;  // friction takes 2/7 of it by design
  out.max_penetration = std::max(0.0, deepest);
  return out;
}

Outcome run_slope_once(const Setting& setting, StepClock& clock) {
  rp::World world = create_world(world_def(setting));
  const double g = -static_cast<double>(world.definition().gravity.y());
  const double theta = kSlopeDegrees * std::numbers::pi / 180;
  const V3 normal(std::sin(theta), std::cos(theta), 0);
  const V3 downhill(std::cos(theta), -std::sin(theta), 0);
  rp::Material material;
  material.friction = static_cast<rp::Real>(kSlopeFriction);
  rp::PlaneDef slope;
  slope.normal = to_real(normal);
  slope.material = material;
  add_plane(world, slope);
  rp::BodyDef def;
  def.position = to_real(kRadius * normal);
  def.radius = static_cast<rp::Real>(kRadius);
  def.material = material;
  def.fast = setting.ccd;
  const rp::BodyId ball = create_body(world, def);
  const V3 start = to_d(state_of(world, ball).position);

  const double a = 5.0 / 7.0 * g * std::sin(theta);
  const auto energy = [&](const rp::BodyState& s) {
    return kinetic_energy(s, 1) + g * static_cast<double>(s.position.y());
  };
  const double e0 = energy(state_of(world, ball));
  const bool record = setting == base_setting();
  Outcome out;
  double deepest = 0;
  const double h = setting.step_s();
  const long steps = std::lround(kSlopeSeconds / h);
  rp::BodyState s;
  for (long n = 1; n <= steps; ++n) {
    clock.step(world, setting);
    s = state_of(world, ball);
    const V3 p = to_d(s.position);
    deepest = std::max(deepest, kRadius - normal.dot(p));
    const double t = static_cast<double>(n) * h;
    if (record)
      out.series.push_back({"s - s_exact", t, (p - start).dot(downhill) - 0.5 * a * t * t});
  }
  const double t = static_cast<double>(steps) * h;
  const double travelled = (to_d(s.position) - start).dot(downhill);
  const double exact = 0.5 * a * t * t;
  const double speed = to_d(s.linear_velocity).norm();
  // Semi-implicit Euler, which moves bodies in contact, runs ahead by ½·a·h·T.
  const double substep = static_cast<double>(static_cast<rp::Real>(setting.dt) /
                                             static_cast<rp::Real>(setting.substeps));
  const std::string note = format(
      "travelled %.5g m vs 1/2*(5/7)*g*sin(theta)*t^2 = %.5g m (%+.3g %%); semi-implicit "
      "Euler offset 1/2*a*h*T = %.4g m; slip speed at the end %.3g m/s (speed %.4g)",
      travelled, exact, 100 * (travelled - exact) / exact, 0.5 * a * substep * t,
      slip_speed(s, normal), speed);
  out.metrics.push_back({"pos_error_2s_m", std::abs(travelled - exact), note});
  // Rolling without slipping conserves energy: no work is done at the contact.
  out.energy_drift = (energy(s) - e0) / std::abs(e0);
  out.max_penetration = std::max(0.0, deepest);
  return out;
}

void sweep(Study& study, const char* scene, Outcome (*run_once)(const Setting&, StepClock&)) {
  const Setting base = base_setting();
  SettingList list;
  list.grid(base, study.integrators(), set_integrator, study.dts(), set_dt);
  list.grid(base, study.corrections(), set_correction, study.iteration_counts(), set_iterations);
  list.vary(base, study.substep_counts(), set_substeps);
  list.vary(base, std::vector<bool>{false, true}, set_ccd);
  for (const Setting& s : list.settings()) study.measure(scene, s, run_once);
}

void report_rolling(Report& r, const char* scene, const std::string& metric,
                    const std::string& metric_title) {
  const Setting base = base_setting();
  const auto precisions = r.precisions();
  const std::string& p0 = precisions.at(0);
  r.text(metric_title + ", integrator × dt (" + p0 + "):");
  r.grid_table(scene, p0, base, kDt, kIntegrator, metric, error_cell());
  r.text(metric_title + ", iterations × position correction (" + p0 + "):");
  r.grid_table(scene, p0, base, kIterations, kCorrection, metric, error_cell());
  r.text("One knob at a time:");
  r.knob_table(
      scene, base, {kSubsteps, kCcd, kDt},
      {{metric_title, metric, error_cell()},
       {"energy drift", metric, [](const ResultRow& row) { return num(row.energy_drift); }},
       {"max penetration, m", metric,
        [](const ResultRow& row) { return num(row.max_penetration); }},
       {"ms/step", metric, ms_cell}});

  Plot cost;
  cost.name = std::string(scene) + "_error_vs_cost";
  cost.title = std::string(scene) + ": " + metric_title + " vs cost (dt 1/30 .. 1/1000)";
  cost.xlabel = "ms of World::step per simulated second";
  cost.ylabel = metric_title;
  cost.logx = cost.logy = true;
  cost.curves = r.curves(
      scene, metric, base, kIntegrator, kDt, [](const ResultRow& row) { return row.ms_per_sim_s; },
      [](const ResultRow& row) { return row.error; });
  r.plot(cost);
}

}  // namespace

void run_slide_to_roll(Study& study) {
  sweep(study, "slide_to_roll", run_slide_once);
}

void run_slope_roll(Study& study) {
  sweep(study, "slope_roll", run_slope_once);
}

void report_slide_to_roll(Report& r) {
  constexpr const char* kScene = "slide_to_roll";
  const auto precisions = r.precisions();
  const std::string& p0 = precisions.at(0);
  r.text(
      "**Reference.** A solid 1 kg sphere (r = 0.5 m) launched at v0 = 5 m/s without spin on a "
      "flat floor, friction 0.3 (ball and floor), restitution 0. Kinetic friction μ·m·g slows it "
      "and spins it up until the contact stops slipping at t_s = 2·v0/(7·μ·g) = 0.485 s; from "
      "then on it rolls at 5/7·v0 = 3.571 m/s (2/7 of the energy is lost in the slip). "
      "**Errors:** |v(3 s) − 5/7·v0| / (5/7·v0), and the distance after 3 s against the "
      "closed form. The note carries the measured slip time. **What to expect.** Friction is "
      "clamped to the Coulomb circle each step, so the slip phase should be right to O(dt); the "
      "final speed is set by angular momentum about the contact point, which the solver "
      "conserves only if friction and the normal impulse are consistent.");
  report_rolling(r, kScene, "rel_error_final_speed", "relative error of the final speed");
  const ResultRow* row = r.results().find(kScene, p0, base_setting(), "rel_error_final_speed");
  const ResultRow* pos = r.results().find(kScene, p0, base_setting(), "pos_error_3s_m");
  if (row && pos) {
    r.text("Base setting: " + row->note + ".");
    r.headline(kScene, format("base: final speed off 5/7·v0 by %s, distance after 3 s off by %s m",
                              percent(row->error).c_str(), num(pos->error).c_str()));
  }
  Plot plot;
  plot.name = "slide_to_roll_speeds";
  plot.title = "Sliding to rolling: v and r*omega vs closed form (base setting, " + p0 + ")";
  plot.xlabel = "t, s";
  plot.ylabel = "m/s";
  plot.commands = {"set key inside right center"};
  for (const char* name : {"v", "r*omega"}) {
    plot.curves.push_back(
        r.series_curve(kScene, p0, name, std::string(name) + " measured", "points pointsize 0.6"));
  }
  const double g = 9.81, mu = kSlideFriction, ts = 2 * kSlideSpeed / (7 * mu * g);
  Curve v{"v closed form",
          {{0, kSlideSpeed}, {ts, 5.0 / 7 * kSlideSpeed}, {1.5, 5.0 / 7 * kSlideSpeed}},
          "lines"};
  Curve w{"r*omega closed form",
          {{0, 0}, {ts, 5.0 / 7 * kSlideSpeed}, {1.5, 5.0 / 7 * kSlideSpeed}},
          "lines dashtype 2"};
  plot.curves.push_back(v);
  plot.curves.push_back(w);
  r.plot(plot);
}

void report_slope_roll(Report& r) {
  constexpr const char* kScene = "slope_roll";
  const auto precisions = r.precisions();
  const std::string& p0 = precisions.at(0);
  r.text(
      "**Reference.** A solid 1 kg sphere (r = 0.5 m) released at rest on a plane tilted 20° "
      "(`add_plane` with normal (sin 20°, cos 20°, 0)), friction 0.5 (≥ 2/7·tan 20° = 0.104, so "
      "it must roll without slipping), restitution 0. Rolling without slipping gives "
      "a = 5/7·g·sin θ = 2.40 m/s², so s(2 s) = 4.80 m. **Error:** |s(2 s) − s_exact| in m; the "
      "note gives the signed relative error and the remaining slip speed. Energy should be "
      "conserved (static friction does no work). **What to expect.** Too little friction "
      "impulse lets it slide (a → g·sin θ, +40 %); locked or over-damped rotation makes it "
      "lag. ExactBallistic and Rk4 integrate a body in contact by semi-implicit Euler "
      "(world_def.h), which runs ahead of the closed form by ½·a·h·T (0.040 m at 1/60, in the "
      "note): if the error equals that figure, the contact itself is exact.");
  report_rolling(r, kScene, "pos_error_2s_m", "position error after 2 s, m");
  const ResultRow* row = r.results().find(kScene, p0, base_setting(), "pos_error_2s_m");
  if (row) {
    r.text("Base setting: " + row->note + ".");
    double offset = 0;
    const auto at = row->note.find("offset 1/2*a*h*T = ");
    if (at != std::string::npos)
      std::sscanf(row->note.c_str() + at, "offset 1/2*a*h*T = %lf", &offset);
    r.headline(kScene, format("base: s(2 s) off the rolling closed form by %s m; semi-implicit "
                              "Euler's ½·a·h·T alone is %s m; energy drift %s",
                              num(row->error).c_str(), num(offset).c_str(),
                              num(row->energy_drift).c_str()));
  }
  Plot plot;
  plot.name = "slope_roll_error_vs_time";
  plot.title = "Rolling down a 20 deg slope: s - s_exact over time (base setting, " + p0 + ")";
  plot.xlabel = "t, s";
  plot.ylabel = "s - 1/2 (5/7) g sin(theta) t^2, m";
  plot.curves.push_back(r.series_curve(kScene, p0, "s - s_exact", "base setting", "lines"));
  r.plot(plot);
}

}  // namespace ricochet::study
