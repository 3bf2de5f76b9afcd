// Stability across time steps from 1/1000 s to 1/10 s: a rain of spheres into a closed box of
// planes (restitution 0.3) and a square pyramid of spheres in a snug box, with the default
// WorldDef (sleeping off, so the solver must hold them). Everything must stay finite and inside,
// no faster than the scene's energy allows, and total mechanical energy (kinetic + potential)
// must never grow from one step to the next beyond what position correction may add.

#include "test_util.h"

namespace ricochet::physics::test::extremes_time_step_test {
namespace {

constexpr Real kTimeSteps[] = {Real(1) / 1000, Real(1) / 240, Real(1) / 60,
                               Real(1) / 30,   Real(1) / 20,  Real(1) / 10};
#if defined(NDEBUG)
constexpr int kRainBodies = 48;
constexpr double kSeconds = 4;  ///< simulated per time step
#else
constexpr int kRainBodies = 16;  // Debug + sanitizers: fewer spheres and seconds, same expectations
constexpr double kSeconds = 2;
#endif

struct Scene {
  World world;
  std::vector<BodyId> ids;
  Real half_width;  ///< m, walls at x, z = ±half_width
  Real height;      ///< m, ceiling (the floor is y = 0)
};

/// Spheres of mixed sizes and masses on a jittered grid 1–6 m up, thrown at up to 2 m/s.
Scene make_rain(const WorldDef& def) {
  Scene scene{make_world(def), {}, 2, 8};
  const Material m = material(Real(0.3), Real(0.5), Real(0.01));
  add_closed_box(scene.world, scene.half_width, scene.height, m);
  Lcg rng(7);
  for (int i = 0; i < kRainBodies; ++i) {
    const int x = i % 4, z = (i / 4) % 4, y = i / 16;
    BodyDef body = sphere_def(Vec3(Real(-1.5 + x + 0.05 * rng.next()), Real(1 + 1.6 * y),
                                   Real(-1.5 + z + 0.05 * rng.next())),
                              rng.uniform(0.2, 0.4), rng.uniform(0.5, 2), m);
    body.linear_velocity = Vec3(rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-2, 2));
    scene.ids.push_back(add_body(scene.world, body));
  }
  return scene;
}

/// A square pyramid, 3×3 + 2×2 + 1 spheres (r = 0.5), each layer in the pockets of the one below,
/// inside walls that touch the base (0.1 mm clearance everywhere).
Scene make_pyramid(const WorldDef& def) {
  const Real r = Real(0.5), gap = Real(1e-4);
  Scene scene{make_world(def), {}, 3 * r + 2 * gap, 6};
  const Material m = material(0, Real(0.6), Real(0.1));
  add_closed_box(scene.world, scene.half_width, scene.height, m);
  for (int layer = 0; layer < 3; ++layer) {
    const int n = 3 - layer;
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        const Real offset = -Real(n - 1) * (r + gap / 2);
        const Vec3 p(offset + Real(i) * (2 * r + gap),
                     r + Real(layer) * (std::sqrt(Real(2)) * r + gap),
                     offset + Real(j) * (2 * r + gap));
        scene.ids.push_back(add_sphere(scene.world, p, r, 1, m));
      }
    }
  }
  return scene;
}

/// What one step's state says about the scene.
struct Measure {
  double energy = 0;        ///< J, kinetic + potential (zero at y = 0)
  double allowance = 0;     ///< J, what position correction may add in the next step (see below)
  double floor_energy = 0;  ///< J, potential energy with every sphere resting on the floor
  std::string problem;      ///< a sphere not finite or outside the box, empty otherwise
  std::vector<BodyState> states;
};

/// Position correction is the one legitimate source of energy: it may lift a body out of an
/// overlap of depth δ (m·g·δ) and, with Baumgarte, leave it the bias velocity that did so,
/// v = min(β·(δ − slop)/dt, max_correction_speed), worth ½·m·v². Each body is charged for its
/// deepest overlap at the start of the step (against a wall or another sphere), which bounds
/// what removing it can supply. Anything more is energy from nowhere.
Measure measure(const Scene& scene, Real dt) {
  const WorldDef& def = scene.world.definition();
  Measure out;
  std::vector<BodyState>& states = out.states;
  for (BodyId id : scene.ids) states.push_back(state_of(scene.world, id));
  for (std::size_t i = 0; i < states.size(); ++i) {
    const BodyState& s = states[i];
    const double r = double(s.radius), mass = 1 / double(s.inverse_mass);
    const Eigen::Vector3d x = to_d(s.position);
    if (!is_finite(s)) {
      out.problem = cat("sphere ", i, " is not finite");
      continue;
    }
    const double w = double(scene.half_width), h = double(scene.height);
    if (std::abs(x.x()) > w || std::abs(x.z()) > w || x.y() < 0 || x.y() > h) {
      out.problem = cat("sphere ", i, " left the box: (", x.transpose(), ")");
    }
    double depth = std::max({r - (x.x() + w), r - (w - x.x()), r - (x.z() + w), r - (w - x.z()),
                             r - x.y(), r - (h - x.y()), 0.0});
    for (std::size_t j = 0; j < states.size(); ++j) {
      if (j == i) continue;
      const double d = (to_d(states[j].position) - x).norm();
      depth = std::max(depth, r + double(states[j].radius) - d);
    }
    const double bias = std::min(
        double(def.baumgarte) * std::max(depth - double(def.linear_slop), 0.0) / double(dt),
        double(def.max_correction_speed));
    out.allowance += mass * (double(kGravity) * depth + 0.5 * bias * bias);
    out.energy += kinetic_energy(s) + potential_energy(s, def.gravity);
    out.floor_energy += mass * double(kGravity) * r;
  }
  // Rounding: E is summed in double from Real states; allow a few Real epsilons of its size.
  out.allowance += 16 * double(kEps) * std::abs(out.energy);
  return out;
}

struct EnergyReport {
  double worst_rise = 0;         ///< J, largest one-step rise of total energy
  double worst_excess = -1e300;  ///< J, largest rise minus its allowance
  int worst_step = -1;
  double start = 0, end = 0;  ///< J
  double peak_speed = 0;      ///< m/s
  double moved = 0;           ///< m, largest distance of any sphere from its start at the end
};

/// Steps the scene for kSeconds and checks every step.
EnergyReport run_checked(Scene& scene, Real dt, const char* name) {
  Measure before = measure(scene, dt);
  std::vector<Eigen::Vector3d> starts;
  for (const BodyState& s : before.states) starts.push_back(to_d(s.position));
  EnergyReport report;
  report.start = before.energy;
  const int steps = steps_for(kSeconds, dt);
  for (int i = 0; i < steps; ++i) {
    if (!run(scene.world, 1, dt)) throw std::runtime_error("step failed");
    Measure now = measure(scene, dt);
    if (!now.problem.empty()) {
      ADD_FAILURE() << name << " dt=1/" << std::lround(1 / double(dt)) << ", step " << i << ": "
                    << now.problem;
      return report;
    }
    // Speed: no sphere can hold more kinetic energy than the scene has above its resting floor
    // level (plus what correction may have added).
    for (const BodyState& s : now.states) {
      const double speed = to_d(s.linear_velocity).norm();
      report.peak_speed = std::max(report.peak_speed, speed);
      const double budget =
          std::sqrt(2 * double(s.inverse_mass) *
                    std::max(report.start - now.floor_energy + now.allowance, 0.0)) +
          1e-6;
      if (speed > budget) {
        ADD_FAILURE() << name << " dt=1/" << std::lround(1 / double(dt)) << ", step " << i
                      << ": speed " << speed << " m/s exceeds the energy budget " << budget;
        return report;
      }
    }
    const double rise = now.energy - before.energy;
    report.worst_rise = std::max(report.worst_rise, rise);
    if (rise - before.allowance > report.worst_excess) {
      report.worst_excess = rise - before.allowance;
      report.worst_step = i;
    }
    before = std::move(now);
  }
  report.end = before.energy;
  for (std::size_t k = 0; k < before.states.size(); ++k) {
    report.moved = std::max(report.moved, (to_d(before.states[k].position) - starts[k]).norm());
  }
  return report;
}

void print_header(const char* name) {
  std::printf("\n  %s, %.0f s per time step\n  %-7s %12s %12s %14s %14s %10s %9s\n", name, kSeconds,
              "dt", "E_start_J", "E_end_J", "worst_rise_J", "rise-allow_J", "peak_v", "moved_m");
}

void print_row(Real dt, const EnergyReport& r) {
  std::printf("  1/%-5ld %12.2f %12.2f %14.3g %14.3g %10.2f %9.4f\n", std::lround(1 / double(dt)),
              r.start, r.end, r.worst_rise, r.worst_excess, r.peak_speed, r.moved);
  std::fflush(stdout);
}

TEST(ExtremeTimeStep, RainStaysInsideAndNeverGainsEnergy) {
  print_header("rain into a closed box, e = 0.3");
  for (const Real dt : kTimeSteps) {
    Scene scene = make_rain(awake_def());
    const EnergyReport r = run_checked(scene, dt, "rain");
    print_row(dt, r);
    EXPECT_LE(r.worst_excess, 0) << "dt=1/" << std::lround(1 / double(dt)) << ": energy rose by "
                                 << r.worst_rise << " J beyond its allowance at step "
                                 << r.worst_step;
    EXPECT_LT(r.end, r.start) << "dt=1/" << std::lround(1 / double(dt));
  }
}

TEST(ExtremeTimeStep, PyramidStaysInsideAndNeverGainsEnergy) {
  print_header("3-layer pyramid in a snug box");
  for (const Real dt : kTimeSteps) {
    Scene scene = make_pyramid(awake_def());
    const EnergyReport r = run_checked(scene, dt, "pyramid");
    print_row(dt, r);
    // Closing the 0.1 mm clearances and contact compliance move spheres by under a millimetre; a
    // layer that slips or a base sphere that rolls out moves by decimetres.
    EXPECT_LT(r.moved, 0.01) << "dt=1/" << std::lround(1 / double(dt)) << ": the pyramid moved";
    EXPECT_LE(r.worst_excess, 0) << "dt=1/" << std::lround(1 / double(dt)) << ": energy rose by "
                                 << r.worst_rise << " J beyond its allowance at step "
                                 << r.worst_step;
  }
}

}  // namespace
}  // namespace ricochet::physics::test::extremes_time_step_test
