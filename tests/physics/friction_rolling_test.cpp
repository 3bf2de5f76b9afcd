// Sliding-to-rolling transition and rolling resistance against the rigid-body closed forms.
//
// A sphere (radius r, I = k·m·r²) launched sliding at v0 with no spin on a floor with Coulomb
// friction μ decelerates at μ·g while its spin grows at μ·g/(k·r), until v = ω·r at
// t* = v0 / (μ·g·(1 + 1/k)); from then on it rolls at v0 / (1 + k): 5/7·v0 for a solid sphere,
// 3/5·v0 for a hollow one. With rolling resistance c (torque c·r·N) a rolling sphere decelerates
// at c·g / (1 + k) and stops after v0² (1 + k) / (2·c·g).

#include "test_util.h"

namespace ricochet::physics::test::friction_rolling_test {
namespace {

constexpr Real kRadius = Real(0.5);

struct SlideCase {
  Real sphere_friction;
  Real floor_friction;
  InertiaModel inertia;
  const char* name;
};

void PrintTo(const SlideCase& c, std::ostream* os) {
  *os << c.name;
}

double inertia_factor(InertiaModel m) {
  return m == InertiaModel::SolidSphere ? 0.4 : 2.0 / 3.0;
}

class SlideToRollTest : public ::testing::TestWithParam<SlideCase> {};

TEST_P(SlideToRollTest, EndsRollingAtOneOverOnePlusKTimesV0) {
  const SlideCase& c = GetParam();
  World world = make_world();  // sleeping off
  add_floor(world, 0, material(0, c.floor_friction));
  BodyDef def = sphere_def(Vec3(0, kRadius, 0), kRadius, 1, material(0, c.sphere_friction));
  def.inertia = c.inertia;
  const Real v0 = 5;
  def.linear_velocity = Vec3(v0, 0, 0);
  const BodyId id = add_body(world, def);

  // Friction combines as the geometric mean of the two coefficients.
  const double mu = std::sqrt(double(c.sphere_friction) * double(c.floor_friction));
  const double g = double(kGravity);
  const double k = inertia_factor(c.inertia);
  const double t_roll = double(v0) / (mu * g * (1 + 1 / k));

  // During the slide (t = 0.25 s < t*): v = v0 − μ·g·t, ω = −μ·g·t / (k·r) about z.
  // 5% of the predicted change: the friction impulse per step is μ times the normal impulse,
  // which equals m·g·dt once the contact has settled (a step or two); an error in μ or in the
  // combination rule (arithmetic mean 0.375 instead of 0.3) moves v by 3x this tolerance.
  const int slide_steps = 15;
  ASSERT_LT(slide_steps * double(kDt60), t_roll);
  ASSERT_TRUE(run(world, slide_steps));
  const double t = slide_steps * double(kDt60);
  BodyState s = state_of(world, id);
  EXPECT_NEAR(s.linear_velocity.x(), double(v0) - mu * g * t, 0.05 * mu * g * t) << c.name;
  EXPECT_NEAR(s.angular_velocity.z(), -mu * g * t / (k * double(kRadius)),
              0.05 * mu * g * t / (k * double(kRadius)))
      << c.name;

  // Rolling at t = 2 s (well after t*): v = v0 / (1 + k) within 2%; no slip at the contact.
  ASSERT_TRUE(run(world, 120 - slide_steps));
  s = state_of(world, id);
  const double v_roll = double(v0) / (1 + k);
  EXPECT_NEAR(s.linear_velocity.x(), v_roll, 0.02 * v_roll) << c.name;
  EXPECT_NEAR(s.linear_velocity.x() + s.angular_velocity.z() * kRadius, 0.0, 0.01 * double(v0))
      << c.name << ": still slipping";
  EXPECT_NEAR(s.linear_velocity.z(), 0.0, 1e-3) << c.name;
  EXPECT_NEAR(s.position.y(), kRadius, 1e-3) << c.name;

  // Without rolling resistance it keeps rolling: after 4 more seconds it has lost < 1%.
  const double v_at_2s = s.linear_velocity.x();
  ASSERT_TRUE(run(world, 240));
  s = state_of(world, id);
  EXPECT_GT(s.linear_velocity.x(), 0.99 * v_at_2s) << c.name;
  EXPECT_LT(s.linear_velocity.x(), 1.01 * v_at_2s) << c.name;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, SlideToRollTest,
    ::testing::Values(SlideCase{Real(0.3), Real(0.3), InertiaModel::SolidSphere, "Solid"},
                      SlideCase{Real(0.6), Real(0.15), InertiaModel::SolidSphere,
                                "SolidGeometricMean"},
                      SlideCase{Real(0.3), Real(0.3), InertiaModel::HollowSphere, "Hollow"}),
    [](const ::testing::TestParamInfo<SlideCase>& info) { return std::string(info.param.name); });

TEST(Friction, FrictionlessSphereSlidesForeverWithoutSpin) {
  // Friction 0 on the sphere: the geometric mean with the floor's 0.6 is 0.
  World world = make_world();
  add_floor(world, 0, material(0, Real(0.6)));
  BodyDef def = sphere_def(Vec3(0, kRadius, 0), kRadius, 1, material(0, 0));
  def.linear_velocity = Vec3(5, 0, 0);
  const BodyId id = add_body(world, def);
  ASSERT_TRUE(run(world, 120));
  const BodyState s = state_of(world, id);
  EXPECT_NEAR(s.linear_velocity.x(), 5.0, 1e-3);
  EXPECT_LT(s.angular_velocity.norm(), 1e-3);
  EXPECT_NEAR(s.position.x(), 10.0, 1e-2);
}

TEST(Friction, RollingResistanceStopsARollingBall) {
  World world = make_world();
  const Real c = Real(0.05);
  add_floor(world, 0, material(0, Real(0.6), c));
  BodyDef def = sphere_def(Vec3(0, kRadius, 0), kRadius, 1, material(0, Real(0.6), c));
  const double v0 = 1;
  def.linear_velocity = Vec3(Real(v0), 0, 0);
  def.angular_velocity = Vec3(0, 0, Real(-v0 / kRadius));  // rolling without slip from the start
  const BodyId id = add_body(world, def);

  const double g = double(kGravity);
  const double a = double(c) * g / (1 + 0.4);  // 0.350 m/s²
  const double t_stop = v0 / a;                // 2.85 s
  const double d_stop = v0 * v0 / (2 * a);     // 1.43 m

  // Mid-way (t = 1 s): v = v0 − a·t within 0.05 m/s (≈15% of the loss so far). A resistance
  // applied as a linear deceleration c·g instead of through the spin (no 1 + k) would be 0.14 m/s
  // off here.
  ASSERT_TRUE(run(world, 60));
  EXPECT_NEAR(state_of(world, id).linear_velocity.x(), v0 - a * 1.0, 0.05);

  // Stopped by 1.25·t_stop, and stays stopped (does not roll back) until 2·t_stop.
  ASSERT_TRUE(run(world, steps_for(1.25 * t_stop, kDt60) - 60));
  EXPECT_LT(state_of(world, id).linear_velocity.norm(), 0.01);
  ASSERT_TRUE(run(world, steps_for(0.75 * t_stop, kDt60)));
  const BodyState s = state_of(world, id);
  EXPECT_LT(s.linear_velocity.norm(), 0.01);
  EXPECT_LT(s.angular_velocity.norm(), 0.02);
  // Stopping distance within 10% of v0²/(2a).
  EXPECT_NEAR(s.position.x(), d_stop, 0.1 * d_stop);
}

TEST(Friction, ZeroRollingResistanceKeepsRolling) {
  World world = make_world();
  add_floor(world, 0, material(0, Real(0.6), 0));
  BodyDef def = sphere_def(Vec3(0, kRadius, 0), kRadius, 1, material(0, Real(0.6), 0));
  def.linear_velocity = Vec3(1, 0, 0);
  def.angular_velocity = Vec3(0, 0, Real(-1 / kRadius));
  const BodyId id = add_body(world, def);
  ASSERT_TRUE(run(world, 300));  // 5 s; with c = 0.05 it would have stopped after 2.85 s
  const BodyState s = state_of(world, id);
  EXPECT_NEAR(s.linear_velocity.x(), 1.0, 0.01);
  EXPECT_NEAR(s.angular_velocity.z(), -2.0, 0.02);
  EXPECT_NEAR(s.position.x(), 5.0, 0.05);
}

TEST(Friction, LockedRotationSlidesAndStops) {
  // lock_rotation gives infinite inertia (k → ∞): no rolling, Coulomb friction stops the sphere
  // after v0 / (μ·g) = 5 / 2.943 = 1.70 s having slid v0² / (2·μ·g) = 4.25 m.
  World world = make_world();
  add_floor(world, 0, material(0, Real(0.3)));
  BodyDef def = sphere_def(Vec3(0, kRadius, 0), kRadius, 1, material(0, Real(0.3)));
  def.lock_rotation = true;
  def.linear_velocity = Vec3(5, 0, 0);
  const BodyId id = add_body(world, def);
  ASSERT_TRUE(run(world, 150));  // 2.5 s
  const BodyState s = state_of(world, id);
  EXPECT_TRUE(s.inverse_inertia_world.isZero());
  EXPECT_TRUE(s.angular_velocity.isZero());
  EXPECT_LT(s.linear_velocity.norm(), 0.01);
  const double d = 25.0 / (2 * 0.3 * double(kGravity));
  EXPECT_NEAR(s.position.x(), d, 0.03 * d);  // 3%: one step of travel at the start is 2%
}

}  // namespace
}  // namespace ricochet::physics::test::friction_rolling_test
