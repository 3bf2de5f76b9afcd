/// Shared study machinery: names, worlds from settings, timed steps, repeats, bookkeeping.

#include "study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <type_traits>

namespace ricochet::study {

const char* precision_name() {
  return std::is_same_v<rp::Real, double> ? "double" : "float";
}

const char* integrator_name(rp::Integrator integrator) {
  switch (integrator) {
    case rp::Integrator::ExplicitEuler:
      return "ExplicitEuler";
    case rp::Integrator::SemiImplicitEuler:
      return "SemiImplicitEuler";
    case rp::Integrator::ExactBallistic:
      return "ExactBallistic";
    case rp::Integrator::Rk4:
      return "Rk4";
  }
  return "?";
}

const char* correction_name(rp::PositionCorrection correction) {
  switch (correction) {
    case rp::PositionCorrection::Baumgarte:
      return "Baumgarte";
    case rp::PositionCorrection::SplitImpulse:
      return "SplitImpulse";
    case rp::PositionCorrection::SoftStep:
      return "SoftStep";
  }
  return "?";
}

bool parse_integrator(const std::string& name, rp::Integrator& out) {
  for (const rp::Integrator i : {rp::Integrator::ExplicitEuler, rp::Integrator::SemiImplicitEuler,
                                 rp::Integrator::ExactBallistic, rp::Integrator::Rk4}) {
    if (name == integrator_name(i)) {
      out = i;
      return true;
    }
  }
  return false;
}

bool parse_correction(const std::string& name, rp::PositionCorrection& out) {
  for (const rp::PositionCorrection c :
       {rp::PositionCorrection::Baumgarte, rp::PositionCorrection::SplitImpulse,
        rp::PositionCorrection::SoftStep}) {
    if (name == correction_name(c)) {
      out = c;
      return true;
    }
  }
  return false;
}

std::string dt_label(double dt) {
  const double per_second = 1 / dt;
  const double rounded = std::round(per_second);
  if (rounded >= 1 && std::abs(per_second - rounded) < 1e-6 * rounded)
    return format("1/%.0f", rounded);
  return format("%g", dt);
}

rp::WorldDef world_def(const Setting& setting) {
  rp::WorldDef def;
  def.integrator = setting.integrator;
  def.iterations = setting.iterations;
  def.substeps = setting.substeps;
  def.position_correction = setting.correction;
  def.enable_continuous = setting.ccd;
  def.enable_sleep = setting.sleep;
  def.contact_events = false;
  return def;
}

void fail(const char* what, const std::string& message) {
  std::fprintf(stderr, "physics-study: %s: %s\n", what, message.c_str());
  std::exit(2);
}

rp::World create_world(const rp::WorldDef& def) {
  return must(rp::World::create(def), "World::create");
}

rp::BodyId create_body(rp::World& world, const rp::BodyDef& def) {
  return must(world.create_body(def), "create_body");
}

void add_plane(rp::World& world, const rp::PlaneDef& def) {
  (void)must(world.add_plane(def), "add_plane");
}

rp::BodyState state_of(const rp::World& world, rp::BodyId id) {
  return must(world.body_state(id), "body_state");
}

void StepClock::step(rp::World& world, const Setting& setting) {
  const rp::Real dt = static_cast<rp::Real>(setting.dt);
  const auto start = std::chrono::steady_clock::now();
  const rp::Status status = world.step(dt);
  const auto end = std::chrono::steady_clock::now();
  if (!status) fail("step", status.error().message);
  total_ms_ += std::chrono::duration<double, std::milli>(end - start).count();
  ++steps_;
}

std::vector<double> Study::dts() const {
  const std::vector<double> all = {1.0 / 30, 1.0 / 60, 1.0 / 120, 1.0 / 240, 1.0 / 480, 1.0 / 1000};
  return pick(all, all, std::vector<double>{1.0 / 60});
}

std::vector<int> Study::iteration_counts() const {
  return pick(std::vector<int>{1, 2, 4, 8, 10, 20, 50}, std::vector<int>{1, 2, 4, 10, 20, 50},
              std::vector<int>{10});
}

std::vector<int> Study::substep_counts() const {
  return pick(std::vector<int>{1, 2, 4, 8}, std::vector<int>{1, 2, 4, 8}, std::vector<int>{1});
}

std::vector<rp::Integrator> Study::integrators() const {
  const std::vector<rp::Integrator> all = {rp::Integrator::ExplicitEuler,
                                           rp::Integrator::SemiImplicitEuler,
                                           rp::Integrator::ExactBallistic, rp::Integrator::Rk4};
  return pick(all, all, std::vector<rp::Integrator>{rp::Integrator::SemiImplicitEuler});
}

std::vector<rp::PositionCorrection> Study::corrections() const {
  const std::vector<rp::PositionCorrection> all = {rp::PositionCorrection::Baumgarte,
                                                   rp::PositionCorrection::SplitImpulse,
                                                   rp::PositionCorrection::SoftStep};
  return pick(all, all, std::vector<rp::PositionCorrection>{rp::PositionCorrection::Baumgarte});
}

void Study::measure(const std::string& scene, const Setting& setting,
                    const std::function<Outcome(const Setting&, StepClock&)>& run) {
  // Short runs are repeated until this much stepping time was measured (or max_repeats).
  const double min_timed_ms = pick(400.0, 30.0, 0.0);
  const int max_repeats = pick(40, 5, 1);

  StepClock clock;
  const Outcome outcome = run(setting, clock);
  std::vector<double> ms_per_step = {clock.total_ms() / std::max(1L, clock.steps())};
  double timed_ms = clock.total_ms();
  while (static_cast<int>(ms_per_step.size()) < max_repeats && timed_ms < min_timed_ms) {
    StepClock again;
    (void)run(setting, again);
    ms_per_step.push_back(again.total_ms() / std::max(1L, again.steps()));
    timed_ms += again.total_ms();
  }
  std::sort(ms_per_step.begin(), ms_per_step.end());
  const double median = ms_per_step[ms_per_step.size() / 2];

  for (const Metric& m : outcome.metrics) {
    Row row;
    row.scene = scene;
    row.setting = setting;
    row.metric = m;
    if (!outcome.note.empty())
      row.metric.note += (row.metric.note.empty() ? "" : "; ") + outcome.note;
    row.ms_per_step = median;
    row.energy_drift = outcome.energy_drift;
    row.max_penetration = outcome.max_penetration;
    rows_.push_back(std::move(row));
  }
  for (const SeriesPoint& p : outcome.series) series_.push_back({scene, p});
}

void SettingList::contact_sweeps(const Study& study, const Setting& base) {
  grid(base, study.corrections(), set_correction, study.iteration_counts(), set_iterations);
  grid(base, study.corrections(), set_correction, study.substep_counts(), set_substeps);
}

void SettingList::add(const Setting& s) {
  if (std::find(settings_.begin(), settings_.end(), s) == settings_.end()) settings_.push_back(s);
}

double kinetic_energy(const rp::BodyState& s, double mass) {
  const V3 v = to_d(s.linear_velocity);
  const V3 w = to_d(s.angular_velocity);
  double energy = 0.5 * mass * v.squaredNorm();
  // Spheres are isotropic: the inverse inertia is a multiple of the identity.
  const double inverse_inertia = static_cast<double>(s.inverse_inertia_world(0, 0));
  if (inverse_inertia > 0) energy += 0.5 * w.squaredNorm() / inverse_inertia;
  return energy;
}

double max_penetration(const std::vector<rp::BodyState>& states,
                       const std::vector<PlaneGeom>& planes) {
  double deepest = 0;
  for (std::size_t i = 0; i < states.size(); ++i) {
    const V3 p = to_d(states[i].position);
    const double r = static_cast<double>(states[i].radius);
    for (const PlaneGeom& plane : planes)
      deepest = std::max(deepest, r - (plane.normal.dot(p) - plane.offset));
    for (std::size_t j = i + 1; j < states.size(); ++j) {
      const double reach = r + static_cast<double>(states[j].radius);
      deepest = std::max(deepest, reach - (to_d(states[j].position) - p).norm());
    }
  }
  return deepest;
}

std::vector<rp::BodyState> states_of(const rp::World& world, const std::vector<rp::BodyId>& ids) {
  std::vector<rp::BodyState> states;
  states.reserve(ids.size());
  for (const rp::BodyId id : ids) states.push_back(state_of(world, id));
  return states;
}

std::string format(const char* fmt, ...) {
  va_list args;
  va_start(args, fmt);
  va_list copy;
  va_copy(copy, args);
  const int n = std::vsnprintf(nullptr, 0, fmt, copy);
  va_end(copy);
  std::string out(static_cast<std::size_t>(std::max(n, 0)), '\0');
  std::vsnprintf(out.data(), out.size() + 1, fmt, args);
  va_end(args);
  return out;
}

}  // namespace ricochet::study
