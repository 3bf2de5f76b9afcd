// World feature switches (WorldDef::enable_rotation, _friction, _rolling_resistance,
// _restitution): each one off removes exactly that behaviour, checked against closed forms.

#include "test_util.h"

namespace ricochet::physics::test {
namespace {

/// A 1 kg ball resting on a floor with friction 0.5, launched sideways at v0.
struct Slide {
  World world;
  BodyId ball;
};

Slide make_slide(const WorldDef& def, Real v0, const Material& m = material(0, Real(0.5))) {
  Slide s{make_world(def), {}};
  add_floor(s.world, 0, m);
  BodyDef ball = sphere_def(Vec3(0, Real(0.5), 0), Real(0.5), 1, m);
  ball.linear_velocity = Vec3(v0, 0, 0);
  s.ball = add_body(s.world, ball);
  return s;
}

TEST(FeatureSwitch, WithoutRotationASlidingBallDeceleratesAtMuGAndNeverSpins) {
  // No rolling: kinetic friction μ·g decelerates it to rest after about v0²/(2μg) metres.
  WorldDef def = awake_def();
  def.enable_rotation = false;
  const Real v0 = 4, mu = Real(0.5);
  Slide s = make_slide(def, v0);
  ASSERT_TRUE(run(s.world, 180));
  const BodyState end = state_of(s.world, s.ball);
  // Semi-implicit steps: v_n = v0 - n·μg·h, x = h·Σ v_n, which is v0²/(2μg) - v0·h/2 + O(h²).
  const Real h = kDt60;
  double expected = 0;
  for (double v = v0 - mu * kGravity * h; v > 0; v -= mu * kGravity * h) expected += v * h;
  EXPECT_NEAR(end.position.x(), expected, Real(0.005));
  EXPECT_NEAR(expected, v0 * v0 / (2 * mu * kGravity) - v0 * h / 2, 0.005);
  EXPECT_LT(end.linear_velocity.norm(), Real(1e-3));
  EXPECT_EQ(end.angular_velocity, Vec3::Zero());
  EXPECT_TRUE(end.orientation.coeffs() == Quat::Identity().coeffs());
}

TEST(FeatureSwitch, WithRotationTheSameBallEndsRollingAtFiveSevenths) {
  const Real v0 = 4;
  Slide s = make_slide(awake_def(), v0);
  ASSERT_TRUE(run(s.world, 180));
  EXPECT_NEAR(state_of(s.world, s.ball).linear_velocity.x(), v0 * 5 / 7, Real(0.02));
}

TEST(FeatureSwitch, WithoutFrictionASlidingBallKeepsItsSpeed) {
  WorldDef def = awake_def();
  def.enable_friction = false;
  const Real v0 = 4;
  Slide s = make_slide(def, v0);
  ASSERT_TRUE(run(s.world, 120));
  const BodyState end = state_of(s.world, s.ball);
  EXPECT_NEAR(end.linear_velocity.x(), v0, Real(1e-4));
  EXPECT_EQ(end.angular_velocity, Vec3::Zero());
}

TEST(FeatureSwitch, WithoutRollingResistanceARollingBallKeepsRolling) {
  // Rolling resistance 0.05 would stop the ball (deceleration ~ (5/7)·c·g); switched off, the
  // rolling speed stays 5/7 v0.
  const Real v0 = 4;
  const Material m = material(0, Real(0.5), Real(0.05));
  WorldDef def = awake_def();
  def.enable_rolling_resistance = false;
  Slide off = make_slide(def, v0, m);
  Slide on = make_slide(awake_def(), v0, m);
  ASSERT_TRUE(run(off.world, 240));
  ASSERT_TRUE(run(on.world, 240));
  EXPECT_NEAR(state_of(off.world, off.ball).linear_velocity.x(), v0 * 5 / 7, Real(0.02));
  EXPECT_LT(state_of(on.world, on.ball).linear_velocity.x(), v0 * 5 / 7 - Real(0.5));
}

TEST(FeatureSwitch, WithoutRestitutionNothingBounces) {
  const Material bouncy = material(Real(0.9), Real(0.5));
  for (const bool restitution : {true, false}) {
    WorldDef def = awake_def();
    def.enable_restitution = restitution;
    World world = make_world(def);
    add_floor(world, 0, bouncy);
    const BodyId ball = add_sphere(world, Vec3(0, 3, 0), Real(0.5), 1, bouncy);
    Real apex_after_impact = 0;
    bool hit = false;
    for (int i = 0; i < 120; ++i) {
      ASSERT_TRUE(run(world, 1));
      const BodyState s = state_of(world, ball);
      hit = hit || s.linear_velocity.y() > 0;
      if (hit) apex_after_impact = std::max(apex_after_impact, s.position.y() - Real(0.5));
    }
    if (restitution) {
      EXPECT_GT(apex_after_impact, Real(2.5 * 0.9 * 0.9 * 0.9)) << "e = 0.9 bounces";
    } else {
      EXPECT_LT(apex_after_impact, Real(0.01)) << "restitution off: no bounce";
    }
  }
}

}  // namespace
}  // namespace ricochet::physics::test
