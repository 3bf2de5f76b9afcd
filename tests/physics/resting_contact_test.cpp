// Resting contact: a sphere on a plane and a pyramid of spheres in a corner must stay put.
//
// Sleeping is disabled in every test here, so the solver itself has to hold the bodies still.

#include "test_util.h"

namespace ricochet::physics::test::resting_contact_test {
namespace {

struct RestCase {
  PositionCorrection correction;
  int substeps;
};

void PrintTo(const RestCase& c, std::ostream* os) {
  *os << correction_name(c.correction) << " x" << c.substeps;
}

class RestingSphereTest : public ::testing::TestWithParam<RestCase> {};

TEST_P(RestingSphereTest, SphereOnPlaneStaysPutForTenSeconds) {
  WorldDef def = awake_def();
  def.position_correction = GetParam().correction;
  def.substeps = GetParam().substeps;
  World world = make_world(def);
  add_floor(world);
  const Vec3 start(Real(0.25), Real(0.5), Real(-0.75));  // exactly touching: bottom at y = 0
  const BodyId id = add_sphere(world, start);

  // Bounds: 1 mm and 1 mm/s. A soft contact at contact_hertz = 30 Hz sags by g/(2π·30)² ≈ 0.3 mm
  // under its own weight; anything beyond 1 mm is drift, not compliance. The speed bound is ~1/160
  // of the g·dt = 0.16 m/s that each step's gravity adds and the contact must cancel.
  double max_drift = 0, max_speed = 0, max_spin = 0;
  for (int i = 0; i < 600; ++i) {  // 10 s at 60 Hz
    ASSERT_TRUE(run(world, 1));
    const BodyState s = state_of(world, id);
    ASSERT_TRUE(is_finite(s)) << "step " << i;
    max_drift = std::max(max_drift, double((s.position - start).norm()));
    max_speed = std::max(max_speed, double(s.linear_velocity.norm()));
    max_spin = std::max(max_spin, double(s.angular_velocity.norm()));
  }
  EXPECT_LT(max_drift, 1e-3) << correction_name(GetParam().correction);
  EXPECT_LT(max_speed, 1e-3) << correction_name(GetParam().correction);
  EXPECT_LT(max_spin, 2e-3) << correction_name(GetParam().correction);  // 1 mm/s at r = 0.5
  EXPECT_FALSE(state_of(world, id).sleeping);
}

INSTANTIATE_TEST_SUITE_P(
    Schemes, RestingSphereTest,
    // SoftStep is meant to run with substeps >= 4 (world_def.h); Baumgarte is the default.
    ::testing::Values(RestCase{PositionCorrection::Baumgarte, 1},
                      RestCase{PositionCorrection::Baumgarte, 4},
                      RestCase{PositionCorrection::SplitImpulse, 1},
                      RestCase{PositionCorrection::SoftStep, 4},
                      RestCase{PositionCorrection::SoftStep, 8}),
    [](const ::testing::TestParamInfo<RestCase>& info) {
      std::string name = correction_name(info.param.correction);
      name += "_substeps";
      name += std::to_string(info.param.substeps);
      return name;
    });

TEST(RestingContact, HeavySphereOnLightSphereOnPlane) {
  // A 10:1 mass ratio stack, exactly aligned: the classic hard case for sequential impulses.
  World world = make_world();
  add_floor(world);
  const Vec3 low(0, Real(0.5), 0), high(0, Real(1.5), 0);
  const BodyId a = add_sphere(world, low, Real(0.5), 1);
  const BodyId b = add_sphere(world, high, Real(0.5), 10);
  ASSERT_TRUE(run(world, 300));
  // 1 cm: two soft contacts in series, each carrying about 11x the weight its effective mass
  // would give it; if the contact stiffness scales with the effective mass (soft step), each
  // sags ≈ 11 · g/(2π·30 Hz)² ≈ 3 mm, 6 mm for the top sphere. A stack that slips or sinks
  // through moves by decimetres.
  EXPECT_LT((state_of(world, a).position - low).norm(), 1e-2);
  EXPECT_LT((state_of(world, b).position - high).norm(), 1e-2);
  EXPECT_LT(state_of(world, b).linear_velocity.norm(), 1e-2);
}

TEST(RestingContact, FourLayerPyramidInCornerHolds) {
  // A square pyramid of 4×4 + 3×3 + 2×2 + 1 = 30 spheres (r = 0.5) in the corner formed by the
  // floor y = 0 and the walls x = 0 and z = 0. Each layer sits in the pockets of the one below
  // (offset r in x and z, √2·r up). The two open sides are held only by the contacts.
  //
  // Material: friction 0.6 and rolling resistance 0.1 everywhere. Point contacts without rolling
  // resistance cannot hold this: nothing resists relative spin about a contact normal, so the
  // base can roll outward without any contact sliding, and Coulomb friction of any size does not
  // stop it (the in-progress implementation collapses with μ = 1 and 50 iterations, like an
  // unframed stack of real balls). Rolling resistance 0.1 (torque 0.1·r·N) is the physical
  // ingredient that holds it; it held with 2x margin there (0.05 sufficed, 0.02 did not).
  World world = make_world();  // sleeping off: the solver must hold it, not sleep
  const Material m = material(0, Real(0.6), Real(0.1));
  add_floor(world, 0, m);
  add_plane(world, Vec3::UnitX(), 0, m);
  add_plane(world, Vec3::UnitZ(), 0, m);
  const Real r = Real(0.5);
  const Real rise = std::sqrt(Real(2)) * r;
  std::vector<BodyId> ids;
  std::vector<Vec3> starts;
  for (int layer = 0; layer < 4; ++layer) {
    const int n = 4 - layer;
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        // A hair of clearance (0.1 mm) so nothing starts interpenetrating through rounding.
        const Real gap = Real(1e-4);
        const Vec3 p(r + Real(layer) * r + Real(i) * (2 * r + gap), r + Real(layer) * (rise + gap),
                     r + Real(layer) * r + Real(j) * (2 * r + gap));
        starts.push_back(p);
        ids.push_back(add_sphere(world, p, r, 1, m));
      }
    }
  }
  ASSERT_EQ(ids.size(), 30u);

  ASSERT_TRUE(run(world, 600));  // 10 s at 60 Hz
  // Bound: 2 cm. Settling into contact compliance and closing the 0.1 mm clearances moves the
  // spheres by millimetres; a sphere that rolls out of the base or a layer that slips moves by
  // decimetres. 2 cm (4% of the radius) separates the two with margin.
  double worst = 0;
  std::size_t worst_index = 0;
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const BodyState s = state_of(world, ids[k]);
    ASSERT_TRUE(is_finite(s)) << "sphere " << k;
    const double moved = (s.position - starts[k]).norm();
    if (moved > worst) {
      worst = moved;
      worst_index = k;
    }
  }
  EXPECT_LT(worst, 0.02) << "sphere " << worst_index << " moved " << worst << " m";
}

}  // namespace
}  // namespace ricochet::physics::test::resting_contact_test
