// Free fall against the closed form x(T) = x0 + v0·T + ½·g·T², for each integrator.
//
// With constant gravity the integrators differ from the closed form by an exact, known amount
// after n steps of size h (T = n·h):
//   SemiImplicitEuler: v += g·h; x += v·h   → x_n = closed form + ½·g·h·T  (falls further)
//   ExplicitEuler:     x += v·h; v += g·h   → x_n = closed form − ½·g·h·T  (falls less)
//   ExactBallistic:    x += v·h + ½·g·h²    → x_n = closed form
// Velocity is v0 + g·T for all three. h is the substep (dt / substeps).

#include "test_util.h"

namespace ricochet::physics::test::free_fall_test {
namespace {

struct FallCase {
  Integrator integrator;
  Real dt;
  int substeps;
  double error_sign;  ///< +1 semi-implicit, −1 explicit, 0 exact (multiplies ½·g·h·T)
  const char* name;
};

void PrintTo(const FallCase& c, std::ostream* os) {
  *os << c.name;
}

class FreeFallTest : public ::testing::TestWithParam<FallCase> {};

TEST_P(FreeFallTest, MatchesClosedFormPlusKnownIntegratorError) {
  const FallCase& c = GetParam();
  WorldDef def = awake_def();
  def.integrator = c.integrator;
  def.substeps = c.substeps;
  World world = make_world(def);  // no statics: nothing but gravity acts

  const Vec3 p0(Real(1), Real(10), Real(-2));
  const Vec3 v0(Real(2), Real(3), Real(-1));
  BodyDef body = sphere_def(p0);
  body.linear_velocity = v0;
  const BodyId id = add_body(world, body);

  const int steps = steps_for(1.0, c.dt);
  ASSERT_TRUE(run(world, steps, c.dt));
  const BodyState s = state_of(world, id);

  // Closed form in double from the exact Real inputs the engine saw.
  const double T = steps * static_cast<double>(c.dt);
  const double h = static_cast<double>(c.dt) / c.substeps;
  const Eigen::Vector3d g = to_d(def.gravity);
  const Eigen::Vector3d closed = to_d(p0) + to_d(v0) * T + 0.5 * g * T * T;
  const Eigen::Vector3d expected = closed + c.error_sign * 0.5 * g * h * T;
  const Eigen::Vector3d expected_v = to_d(v0) + g * T;

  // Tolerance: pure rounding. Per update the position gains at most ½ ulp of |x| ≲ 15 m plus the
  // integral of the velocity's accumulated rounding; worst case ≈ 0.4·eps·15 m per update, so
  // 4·eps·15 m per update is a 10x margin (float, 60 updates: 4.3e-4 m). That is still ~200x
  // smaller than the integrator error ½·g·h·T (0.082 m at 60 Hz) separating the three cases.
  const double updates = steps * c.substeps;
  const double tol = updates * 4.0 * static_cast<double>(kEps) * 15.0;

  EXPECT_NEAR(s.position.x(), expected.x(), tol) << c.name;
  EXPECT_NEAR(s.position.y(), expected.y(), tol) << c.name << " closed form " << closed.y();
  EXPECT_NEAR(s.position.z(), expected.z(), tol) << c.name;
  EXPECT_NEAR(s.linear_velocity.x(), expected_v.x(), tol) << c.name;
  EXPECT_NEAR(s.linear_velocity.y(), expected_v.y(), tol) << c.name;
  EXPECT_NEAR(s.linear_velocity.z(), expected_v.z(), tol) << c.name;

  // The sign of the error, stated directly: semi-implicit ends below the closed form, explicit
  // above it, by ½·g·h·T.
  const double error_y = static_cast<double>(s.position.y()) - closed.y();
  const double magnitude = 0.5 * static_cast<double>(kGravity) * h * T;
  if (c.error_sign > 0) {
    EXPECT_LT(error_y, -0.9 * magnitude) << c.name;
  } else if (c.error_sign < 0) {
    EXPECT_GT(error_y, 0.9 * magnitude) << c.name;
  }
  EXPECT_TRUE(s.angular_velocity.isZero()) << c.name;
}

INSTANTIATE_TEST_SUITE_P(
    Integrators, FreeFallTest,
    ::testing::Values(
        FallCase{Integrator::SemiImplicitEuler, Real(1) / 60, 1, +1, "SemiImplicit60"},
        FallCase{Integrator::SemiImplicitEuler, Real(1) / 120, 1, +1, "SemiImplicit120"},
        FallCase{Integrator::SemiImplicitEuler, Real(1) / 60, 4, +1, "SemiImplicit60x4"},
        FallCase{Integrator::ExplicitEuler, Real(1) / 60, 1, -1, "Explicit60"},
        FallCase{Integrator::ExplicitEuler, Real(1) / 30, 2, -1, "Explicit30x2"},
        FallCase{Integrator::ExactBallistic, Real(1) / 60, 1, 0, "Exact60"},
        FallCase{Integrator::ExactBallistic, Real(1) / 30, 4, 0, "Exact30x4"}),
    [](const ::testing::TestParamInfo<FallCase>& info) { return std::string(info.param.name); });

TEST(FreeFall, ErrorHalvesWhenTheStepHalves) {
  // Semi-implicit error ½·g·dt·T is linear in dt.
  auto fall_error = [](Real dt) {
    World world = make_world();
    const BodyId id = add_sphere(world, Vec3(0, 20, 0));
    const int steps = steps_for(1.0, dt);
    run_or_throw(world, steps, dt);
    const double T = steps * static_cast<double>(dt);
    return static_cast<double>(state_of(world, id).position.y()) -
           (20.0 - 0.5 * static_cast<double>(kGravity) * T * T);
  };
  const double e60 = fall_error(Real(1) / 60);
  const double e120 = fall_error(Real(1) / 120);
  ASSERT_LT(e60, 0);
  // Ratio exactly 2 up to rounding (1e-3 absolute on errors of 0.08 m and 0.04 m).
  EXPECT_NEAR(e60 / e120, 2.0, 0.05);
}

TEST(FreeFall, GravityScaleMultipliesGravity) {
  World world = make_world();
  BodyDef none = sphere_def(Vec3(0, 10, 0));
  none.gravity_scale = 0;
  BodyDef half = sphere_def(Vec3(5, 10, 0));
  half.gravity_scale = Real(0.5);
  BodyDef twice = sphere_def(Vec3(10, 10, 0));
  twice.gravity_scale = 2;
  const BodyId a = add_body(world, none);
  const BodyId b = add_body(world, half);
  const BodyId c = add_body(world, twice);
  ASSERT_TRUE(run(world, 30));
  const double T = 30 * static_cast<double>(kDt60);
  const double g = static_cast<double>(kGravity);
  // Velocity after n steps is scale·g·T for every integrator; rounding only (30 updates).
  EXPECT_EQ(state_of(world, a).position, Vec3(0, 10, 0));
  EXPECT_TRUE(state_of(world, a).linear_velocity.isZero());
  EXPECT_NEAR(state_of(world, b).linear_velocity.y(), -0.5 * g * T, 1e-4);
  EXPECT_NEAR(state_of(world, c).linear_velocity.y(), -2.0 * g * T, 1e-4);
}

TEST(FreeFall, SetGravityTakesEffectOnTheNextStep) {
  World world = make_world();
  const BodyId id = add_sphere(world, Vec3(0, 50, 0));
  ASSERT_TRUE(run(world, 30));
  RICOCHET_ASSERT_OK(world.set_gravity(Vec3(Real(2), 0, 0)));
  ASSERT_TRUE(run(world, 30));
  const BodyState s = state_of(world, id);
  const double T = 30 * static_cast<double>(kDt60);
  EXPECT_NEAR(s.linear_velocity.y(), -static_cast<double>(kGravity) * T, 1e-4);
  EXPECT_NEAR(s.linear_velocity.x(), 2.0 * T, 1e-4);
}

}  // namespace
}  // namespace ricochet::physics::test::free_fall_test
