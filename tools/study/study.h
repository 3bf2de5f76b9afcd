#pragma once
/// The accuracy ↔ speed study: one measured setting of the engine's knobs, the rows it produces,
/// and what every scene shares (a world from a setting, timed stepping, repeats for stable
/// timings, energy and penetration in double).
///
/// A scene runs a list of settings (one knob at a time around its base, plus the 2-D grids its
/// plots need); each run yields one row per error measure. Only World::step is timed.

#include <Eigen/Core>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "ricochet/physics/world.h"

namespace ricochet::study {

namespace rp = ricochet::physics;
using V3 = Eigen::Vector3d;

inline V3 to_d(const rp::Vec3& v) {
  return v.cast<double>();
}
inline rp::Vec3 to_real(const V3& v) {
  return v.cast<rp::Real>();
}

/// "float" or "double": the scalar this binary's physics was built with.
const char* precision_name();

/// How much to run. Full: every sweep, long scenes, enough repeats for stable timings. Quick: the
/// same scenes and plots on shorter runs and fewer points. Smoke: one or two settings per scene,
/// seconds in a sanitizer build.
enum class Mode { Full, Quick, Smoke };

/// The engine knobs of one measured run.
struct Setting {
  rp::Integrator integrator = rp::Integrator::SemiImplicitEuler;
  double dt = 1.0 / 60;  ///< s, before rounding to Real
  int iterations = 10;
  int substeps = 1;
  rp::PositionCorrection correction = rp::PositionCorrection::Baumgarte;
  bool ccd = false;     ///< WorldDef::enable_continuous and BodyDef::fast on moving bodies
  bool sleep = true;    ///< WorldDef::enable_sleep
  std::string variant;  ///< scene parameter such as "e=0.9"; empty when the scene has none

  /// The step the engine really takes: dt rounded to Real, back in double.
  double step_s() const { return static_cast<double>(static_cast<rp::Real>(dt)); }
  friend bool operator==(const Setting&, const Setting&) = default;
};

const char* integrator_name(rp::Integrator integrator);
const char* correction_name(rp::PositionCorrection correction);
bool parse_integrator(const std::string& name, rp::Integrator& out);
bool parse_correction(const std::string& name, rp::PositionCorrection& out);
/// "1/60" for 1/60 s, the plain number otherwise.
std::string dt_label(double dt);

/// The WorldDef of a setting (gravity and other scene choices are set by the scene afterwards).
/// Contact events are off: no scene reads them, and the rain bench measures without them too.
rp::WorldDef world_def(const Setting& setting);
/// Reports a failed engine call that cannot fail in a correct scene (a study bug) and exits.
[[noreturn]] void fail(const char* what, const std::string& message);
/// The value of such a call; exits with the engine's message when it failed.
template <class T>
T must(rp::Result<T> result, const char* what) {
  if (!result) fail(what, result.error().message);
  return std::move(result).value();
}
rp::World create_world(const rp::WorldDef& def);
rp::BodyId create_body(rp::World& world, const rp::BodyDef& def);
void add_plane(rp::World& world, const rp::PlaneDef& def);
rp::BodyState state_of(const rp::World& world, rp::BodyId id);

/// Steps a world and accumulates the wall time spent inside World::step only.
class StepClock {
 public:
  void step(rp::World& world, const Setting& setting);
  double total_ms() const { return total_ms_; }
  long steps() const { return steps_; }

 private:
  double total_ms_ = 0;
  long steps_ = 0;
};

/// One error measure of a run. `error` is what the metric's name says (units in the name).
struct Metric {
  std::string name;
  double error = 0;
  std::string note;
};

/// A point of a curve for the plots (energy against time, apex against bounce number...).
struct SeriesPoint {
  std::string series;
  double x = 0;
  double y = 0;
};

/// What one run of a scene at one setting measured.
struct Outcome {
  std::vector<Metric> metrics;
  double energy_drift = 0;     ///< (E_end - E_start) / |E_start|, signed
  double max_penetration = 0;  ///< m, largest overlap seen during the run
  std::string note;            ///< appended to every metric's note
  std::vector<SeriesPoint> series;
};

/// One line of results.csv, before the precision column is added.
struct Row {
  std::string scene;
  Setting setting;
  Metric metric;
  double ms_per_step = 0;
  double energy_drift = 0;
  double max_penetration = 0;
};

struct SeriesRow {
  std::string scene;
  SeriesPoint point;
};

/// Runs settings, repeats them for timing, and collects rows and series.
class Study {
 public:
  explicit Study(Mode mode) : mode_(mode) {}

  Mode mode() const { return mode_; }
  bool smoke() const { return mode_ == Mode::Smoke; }
  bool full() const { return mode_ == Mode::Full; }
  /// Picks the value for the current mode.
  template <class T>
  T pick(T full, T quick, T smoke) const {
    return mode_ == Mode::Full ? full : mode_ == Mode::Quick ? quick : smoke;
  }

  // The sweep axes, thinned in quick and smoke mode.
  std::vector<double> dts() const;
  std::vector<int> iteration_counts() const;
  std::vector<int> substep_counts() const;
  std::vector<rp::Integrator> integrators() const;
  std::vector<rp::PositionCorrection> corrections() const;

  /// Runs `run` at `setting` (once for the error measures, then again until the timed total is
  /// long enough for a stable median ms/step) and records one row per metric plus the series of
  /// the first run.
  void measure(const std::string& scene, const Setting& setting,
               const std::function<Outcome(const Setting&, StepClock&)>& run);

  const std::vector<Row>& rows() const { return rows_; }
  const std::vector<SeriesRow>& series() const { return series_; }

 private:
  Mode mode_;
  std::vector<Row> rows_;
  std::vector<SeriesRow> series_;
};

/// A list of distinct settings built from sweeps around a base.
class SettingList {
 public:
  void add(const Setting& s);
  /// The base with one knob set to each value in turn.
  template <class T, class Set>
  void vary(const Setting& base, const std::vector<T>& values, Set&& set) {
    for (const T& v : values) {
      Setting s = base;
      set(s, v);
      add(s);
    }
  }
  /// Every combination of two knobs around the base.
  template <class A, class SetA, class B, class SetB>
  void grid(const Setting& base, const std::vector<A>& as, SetA&& set_a, const std::vector<B>& bs,
            SetB&& set_b) {
    for (const A& a : as) {
      Setting s = base;
      set_a(s, a);
      vary(s, bs, set_b);
    }
  }
  /// The contact-solver sweeps: position correction × iterations and × substeps.
  void contact_sweeps(const Study& study, const Setting& base);
  const std::vector<Setting>& settings() const { return settings_; }

 private:
  std::vector<Setting> settings_;
};

// Setters for SettingList::vary / grid.
inline void set_integrator(Setting& s, rp::Integrator v) {
  s.integrator = v;
}
inline void set_dt(Setting& s, double v) {
  s.dt = v;
}
inline void set_iterations(Setting& s, int v) {
  s.iterations = v;
}
inline void set_substeps(Setting& s, int v) {
  s.substeps = v;
}
inline void set_correction(Setting& s, rp::PositionCorrection v) {
  s.correction = v;
}
inline void set_ccd(Setting& s, bool v) {
  s.ccd = v;
}
inline void set_sleep(Setting& s, bool v) {
  s.sleep = v;
}

// --- physics bookkeeping, in double ---

/// Linear plus rotational kinetic energy, J.
double kinetic_energy(const rp::BodyState& s, double mass);
/// A static plane as the scene built it: the solid is below normal·x = offset.
struct PlaneGeom {
  V3 normal;
  double offset = 0;
};
/// m: the deepest overlap among the bodies (equal radius or not) and against the planes, >= 0.
double max_penetration(const std::vector<rp::BodyState>& states,
                       const std::vector<PlaneGeom>& planes);
std::vector<rp::BodyState> states_of(const rp::World& world, const std::vector<rp::BodyId>& ids);

/// printf into a std::string.
std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));

}  // namespace ricochet::study
