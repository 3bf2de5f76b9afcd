/// Scene 1: a projectile under gravity against x0 + v0·t + ½·g·t².
///
/// No contacts, so only the integrator, dt and substeps matter. Over N steps of h the Euler
/// schemes are off by exactly ½·g·h·T (explicit Euler falls short, semi-implicit overshoots);
/// ExactBallistic and Rk4 are exact for constant acceleration and show round-off only.

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "scenes.h"

namespace ricochet::study {

namespace {

constexpr const char* kScene = "projectile";
const V3 kStartVelocity(10, 10, 0);  // m/s

Setting base_setting() {
  return Setting{};
}

/// The substep the engine takes, as it computes it (in Real).
double substep_s(const Setting& s) {
  return static_cast<double>(static_cast<rp::Real>(s.dt) / static_cast<rp::Real>(s.substeps));
}

Outcome run_once(const Setting& setting, StepClock& clock) {
  rp::World world = create_world(world_def(setting));
  const V3 g = to_d(world.definition().gravity);  // as the engine holds it
  rp::BodyDef def;
  def.linear_velocity = to_real(kStartVelocity);
  def.fast = setting.ccd;
  const rp::BodyId ball = create_body(world, def);
  const double h = setting.step_s();

  Outcome out;
  long steps = 0;
  for (const double seconds : {1.0, 10.0}) {
    const long target = std::lround(seconds / h);
    while (steps < target) {
      clock.step(world, setting);
      ++steps;
    }
    const double t = static_cast<double>(steps) * h;
    const V3 exact = kStartVelocity * t + 0.5 * g * t * t;
    const rp::BodyState s = state_of(world, ball);
    const double error = (to_d(s.position) - exact).norm();
    Metric m{format("pos_error_%.0fs_m", seconds), error, {}};
    const bool euler = setting.integrator == rp::Integrator::ExplicitEuler ||
                       setting.integrator == rp::Integrator::SemiImplicitEuler;
    if (euler) {
      const double predicted = 0.5 * g.norm() * substep_s(setting) * t;
      m.note = format("predicted 1/2*g*h*T = %.6g m; measured/predicted = %.6f", predicted,
                      error / predicted);
    } else {
      m.note = "predicted 0 (exact for constant acceleration): round-off only";
    }
    out.metrics.push_back(std::move(m));
    if (seconds == 10.0) {
      const double e0 = 0.5 * kStartVelocity.squaredNorm();
      const double e1 = 0.5 * to_d(s.linear_velocity).squaredNorm() - g.dot(to_d(s.position));
      out.energy_drift = (e1 - e0) / e0;
    }
  }
  return out;
}

/// The predicted ½·g·h·T and measured/predicted ratio from an Euler row's note.
bool prediction_of(const ResultRow& row, double& predicted, double& ratio) {
  return std::sscanf(row.note.c_str(), "predicted 1/2*g*h*T = %lf m; measured/predicted = %lf",
                     &predicted, &ratio) == 2;
}

}  // namespace

void run_projectile(Study& study) {
  const Setting base = base_setting();
  SettingList list;
  list.grid(base, study.integrators(), set_integrator, study.dts(), set_dt);
  list.grid(base, study.integrators(), set_integrator, study.substep_counts(), set_substeps);
  for (const Setting& s : list.settings()) study.measure(kScene, s, run_once);
}

void report_projectile(Report& r) {
  const Results& results = r.results();
  const Setting base = base_setting();
  const auto precisions = r.precisions();
  r.text(
      "**Reference.** A 1 kg sphere launched at v0 = (10, 10, 0) m/s with gravity only (no "
      "statics, no contacts) against the closed form x0 + v0·t + ½·g·t², after 1 s and 10 s. "
      "**What to expect.** Explicit Euler (x += v·h, then v += g·h) ends ½·g·h·T short of the "
      "closed form, semi-implicit Euler (v first) ½·g·h·T beyond it: first order in h, so halving "
      "dt (or doubling substeps) halves the error. ExactBallistic adds the ½·a·h² term and Rk4 "
      "integrates constant acceleration exactly: their error is round-off. In float that "
      "round-off is not small: after 10 s the ball is ~400 m from the origin, where a float "
      "step is ~3e-5 m, and thousands of x += v·h additions accumulate centimetres. The `note` "
      "column of each Euler row carries the predicted ½·g·h·T and the measured ratio.");

  std::vector<std::string> header = {"integrator", "dt", "½·g·h·T at 10 s, m"};
  for (const std::string& p : precisions) {
    header.push_back("error 1 s, m (" + p + ")");
    header.push_back("error 10 s, m (" + p + ")");
    header.push_back("measured / ½ghT (" + p + ")");
  }
  header.push_back("ms per simulated s (" + precisions.at(0) + ")");
  std::vector<std::vector<std::string>> rows;
  for (const ResultRow* row :
       results.select(kScene, precisions.at(0), "pos_error_10s_m", base, kIntegrator | kDt)) {
    const Setting& s = row->setting;
    double predicted = 0, ratio = 0;
    const bool euler = prediction_of(*row, predicted, ratio);
    std::vector<std::string> cells = {integrator_name(s.integrator), dt_label(s.dt),
                                      euler ? num(predicted) : "0"};
    for (const std::string& p : precisions) {
      const ResultRow* at1 = results.find(kScene, p, s, "pos_error_1s_m");
      const ResultRow* at10 = results.find(kScene, p, s, "pos_error_10s_m");
      cells.push_back(at1 ? num(at1->error) : "—");
      cells.push_back(at10 ? num(at10->error) : "—");
      cells.push_back(at10 && prediction_of(*at10, predicted, ratio) ? format("%.4f", ratio) : "—");
    }
    cells.push_back(num(row->ms_per_sim_s));
    rows.push_back(std::move(cells));
  }
  r.table(header, rows);

  // The check: explicit Euler's error is ½·g·h·T to 1 %, plus the round-off that ExactBallistic
  // shows at the same dt and precision.
  std::string check, headline;
  for (const std::string& p : precisions) {
    Setting euler = base;
    euler.integrator = rp::Integrator::ExplicitEuler;
    double lo = 1e300, hi = -1e300;
    int within = 0, plain = 0, total = 0;
    for (const ResultRow* row : results.select(kScene, p, "pos_error_10s_m", euler, kDt)) {
      double predicted = 0, ratio = 0;
      if (!prediction_of(*row, predicted, ratio)) continue;
      Setting exact = row->setting;
      exact.integrator = rp::Integrator::ExactBallistic;
      const ResultRow* floor = results.find(kScene, p, exact, "pos_error_10s_m");
      const double roundoff = floor ? floor->error : 0;
      ++total;
      plain += std::abs(ratio - 1) <= 0.01;
      within += std::abs(row->error - predicted) <= 0.01 * predicted + roundoff;
      lo = std::min(lo, ratio);
      hi = std::max(hi, ratio);
    }
    if (total == 0) continue;
    check += format(
        "- **%s**: measured / predicted = %.4f … %.4f; within 1 %% at %d of %d dt; within 1 %% "
        "plus the round-off floor (the ExactBallistic error at the same dt) at %d of %d: %s.\n",
        p.c_str(), lo, hi, plain, total, within, total,
        within == total ? "**the prediction holds**" : "**the prediction does NOT hold**");
    headline += format("%s%s: measured/predicted %.4f … %.4f, %d/%d dt within 1 %% + round-off",
                       headline.empty() ? "" : "; ", p.c_str(), lo, hi, within, total);
  }
  if (!check.empty()) r.text("**Check (explicit Euler vs ½·g·h·T after 10 s):**\n\n" + check);

  std::string floors;
  for (const std::string& p : precisions) {
    double worst = 0;
    for (const rp::Integrator i : {rp::Integrator::ExactBallistic, rp::Integrator::Rk4}) {
      Setting s = base;
      s.integrator = i;
      for (const ResultRow* row : results.select(kScene, p, "pos_error_10s_m", s, kDt))
        worst = std::max(worst, row->error);
    }
    floors += format("%s%s %s m", floors.empty() ? "" : ", ", p.c_str(), num(worst).c_str());
  }
  r.text("Largest ExactBallistic / Rk4 error after 10 s over all dt (round-off): " + floors + ".");
  if (!headline.empty()) {
    r.headline(kScene, "explicit Euler's error after 10 s vs ½·g·h·T (dt 1/30 … 1/1000) — " +
                           headline + "; ExactBallistic/Rk4 round-off only (" + floors + ")");
  }

  r.text(
      "Substeps divide the integration step (the same ½·g·h·T law with h = dt/substeps) and "
      "cost a little per step; for the exact integrators they only add round-off.");
  for (const rp::Integrator i :
       {rp::Integrator::ExplicitEuler, rp::Integrator::SemiImplicitEuler, rp::Integrator::Rk4}) {
    Setting s = base;
    s.integrator = i;
    r.text(std::string("Substeps with ") + integrator_name(i) + ":");
    r.knob_table(kScene, s, {kSubsteps},
                 {{"error 10 s, m", "pos_error_10s_m", error_cell()},
                  {"ms/step", "pos_error_10s_m", ms_cell}});
  }

  Plot plot;
  plot.name = "projectile_error_vs_cost";
  plot.title = "Projectile: position error after 10 s vs cost (dt 1/30 .. 1/1000)";
  plot.xlabel = "ms of World::step per simulated second";
  plot.ylabel = "|x - x_exact| after 10 s, m";
  plot.logx = plot.logy = true;
  plot.curves = r.curves(
      kScene, "pos_error_10s_m", base, kIntegrator, kDt,
      [](const ResultRow& row) { return row.ms_per_sim_s; },
      [](const ResultRow& row) { return row.error; });
  r.plot(plot);
}

}  // namespace ricochet::study
