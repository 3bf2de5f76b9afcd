// Total mechanical energy (linear + rotational kinetic + gravitational potential) must never grow
// in a closed box with restitution < 1: impacts, friction and rolling resistance only remove
// energy, and semi-implicit Euler itself loses ½·m·g²·dt² per free-flight step.
//
// Per-step allowance: position correction may lift a body out of an overlap, which is the one
// legitimate source of new potential energy. We allow every body to be lifted by the full
// linear_slop in one step, N·m·g·linear_slop (64 bodies: 3.1 J against ≈ 2 kJ total, 0.15%),
// plus rounding. A solver that injects energy on impact (e.g. restitution applied to an
// already-separating contact, or Baumgarte pushing at 4 m/s) exceeds it by an order of magnitude.

#include "test_util.h"

namespace ricochet::physics::test::energy_test {
namespace {

struct EnergyScene {
  World world;
  std::vector<BodyId> bodies;
  Vec3 gravity;
};

EnergyScene throw_spheres(PositionCorrection correction, Real restitution, int count,
                          std::uint64_t seed) {
  const WorldDef def = with_correction(awake_def(), correction);
  EnergyScene scene{make_world(def), {}, def.gravity};
  const Real half = 3, height = 6;
  add_closed_box(scene.world, half, height, material(restitution, Real(0.5)));
  Lcg rng(seed);
  const Real r = Real(0.3);
  const int side = 4;  // up to 4×4×4 on a 1.2 m grid, centred
  for (int i = 0; i < count; ++i) {
    const int x = i % side, z = (i / side) % side, y = i / (side * side);
    BodyDef def_body =
        sphere_def(Vec3(Real(-1.8 + 1.2 * x), Real(1.0 + 1.2 * y), Real(-1.8 + 1.2 * z)), r,
                   Real(rng.uniform(0.5, 2.0)), material(restitution, Real(0.5), Real(0.01)));
    def_body.linear_velocity = Vec3(rng.uniform(-8, 8), rng.uniform(-8, 8), rng.uniform(-8, 8));
    def_body.angular_velocity = Vec3(rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-5, 5));
    def_body.inertia = (i % 3 == 0) ? InertiaModel::HollowSphere : InertiaModel::SolidSphere;
    scene.bodies.push_back(add_body(scene.world, def_body));
  }
  return scene;
}

struct EnergyReport {
  double total = 0;
  double weight = 0;  ///< Σ m·g, for the allowance
  bool finite = true;
  bool inside = true;
};

EnergyReport measure(const EnergyScene& scene) {
  EnergyReport r;
  for (BodyId id : scene.bodies) {
    const BodyState s = state_of(scene.world, id);
    r.finite = r.finite && is_finite(s);
    r.inside = r.inside && s.position.y() > 0 && s.position.y() < 6 &&
               std::abs(s.position.x()) < 3 && std::abs(s.position.z()) < 3;
    r.total += kinetic_energy(s) + potential_energy(s, scene.gravity);
    r.weight += double(kGravity) / double(s.inverse_mass);
  }
  return r;
}

struct EnergyCase {
  PositionCorrection correction;
  Real restitution;
};

void PrintTo(const EnergyCase& c, std::ostream* os) {
  *os << correction_name(c.correction) << " e=" << c.restitution;
}

class EnergyTest : public ::testing::TestWithParam<EnergyCase> {};

TEST_P(EnergyTest, NeverIncreasesInClosedBox) {
  const EnergyCase& c = GetParam();
#if defined(NDEBUG)
  const int count = 64;
#else
  const int count = 40;  // Debug + sanitizers: fewer spheres, same physics
#endif
  EnergyScene scene = throw_spheres(c.correction, c.restitution, count, 12345);
  const double slop = double(scene.world.definition().linear_slop);
  EnergyReport before = measure(scene);
  const double e0 = before.total;
  const double allowance = before.weight * slop + 1e3 * double(kEps) * std::abs(e0);
  double worst_rise = -1e300;
  int worst_step = -1;
  for (int i = 0; i < 240; ++i) {  // 4 s at 60 Hz: many impacts, then a settling pile
    ASSERT_TRUE(run(scene.world, 1));
    const EnergyReport now = measure(scene);
    ASSERT_TRUE(now.finite) << "step " << i;
    ASSERT_TRUE(now.inside) << "a sphere left the box at step " << i;
    const double rise = now.total - before.total;
    if (rise > worst_rise) {
      worst_rise = rise;
      worst_step = i;
    }
    EXPECT_LE(now.total, e0 + allowance) << "step " << i << ": above the initial energy";
    before = now;
  }
  EXPECT_LE(worst_rise, allowance) << "largest one-step rise at step " << worst_step
                                   << " (allowance " << allowance << " J, E0 " << e0 << " J)";
  // Sanity: with e < 1 and friction the box has lost a good part of its kinetic energy.
  EXPECT_LT(before.total, e0);
}

INSTANTIATE_TEST_SUITE_P(
    Cases, EnergyTest,
    // Baumgarte (the default) is documented to add energy when it corrects penetration; the
    // per-step allowance is exactly the budget for that correction (lifting by up to the slop).
    ::testing::Values(EnergyCase{PositionCorrection::Baumgarte, Real(0.5)},
                      EnergyCase{PositionCorrection::Baumgarte, Real(0)},
                      EnergyCase{PositionCorrection::SoftStep, Real(0.5)},
                      EnergyCase{PositionCorrection::SplitImpulse, Real(0.5)}),
    [](const ::testing::TestParamInfo<EnergyCase>& info) {
      std::string name = correction_name(info.param.correction);
      name += "_e";
      name += std::to_string(int(std::lround(double(info.param.restitution) * 10)));
      return name;
    });

TEST(Energy, ZeroGravityElasticGasConservesEnergyWithinAllowance) {
  // No gravity, e = 1 everywhere, no friction: kinetic energy is conserved by every impact. Speeds
  // exceed the restitution threshold. Allow 0.5% drift over 2 s (each of the ~100 impacts may be
  // resolved against a velocity one step stale).
  World world = make_world(space_def());
  add_closed_box(world, 3, 6, material(1, 0));
  Lcg rng(99);
  std::vector<BodyId> ids;
  for (int i = 0; i < 27; ++i) {
    const int x = i % 3, z = (i / 3) % 3, y = i / 9;
    BodyDef def = sphere_def(Vec3(Real(-1.5 + 1.5 * x), Real(1.5 + 1.5 * y), Real(-1.5 + 1.5 * z)),
                             Real(0.3), 1, material(1, 0));
    Vec3 v(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    def.linear_velocity = v.normalized() * Real(4);
    ids.push_back(add_body(world, def));
  }
  auto energy = [&] {
    double e = 0;
    for (BodyId id : ids) e += kinetic_energy(state_of(world, id));
    return e;
  };
  const double e0 = energy();
  double e_max = e0;
  for (int i = 0; i < 120; ++i) {
    ASSERT_TRUE(run(world, 1));
    e_max = std::max(e_max, energy());
  }
  EXPECT_LE(e_max, e0 * 1.005);
  EXPECT_GE(energy(), e0 * 0.9) << "an elastic frictionless gas should keep its energy";
}

}  // namespace
}  // namespace ricochet::physics::test::energy_test
