// World feature switches (WorldDef::enable_rotation, _friction, _rolling_resistance,
// _restitution): each one off removes exactly that behaviour. Every test runs the engine and
// compares it either with a closed form of the physics, or with a second world that models the
// same physics another way (a switch off must behave like the material or body flag that removes
// the same effect), and the switch on must show the effect it removes.

#include <numbers>

#include "test_util.h"

namespace ricochet::physics::test::feature_switch_test {
namespace {

constexpr Real kR = Real(0.5);   ///< m, ball radius
constexpr Real kMu = Real(0.5);  ///< friction of ball and floor (so of the contact)
constexpr Real kV0 = 4;          ///< m/s, launch speed along +x

/// A 1 kg ball resting on a floor, both of material m, launched along +x at v0.
struct Slide {
  World world;
  BodyId ball;
};

Slide make_slide(const WorldDef& def, const Material& m = material(0, kMu),
                 bool lock_rotation = false) {
  Slide s{make_world(def), {}};
  add_floor(s.world, 0, m);
  BodyDef ball = sphere_def(Vec3(0, kR, 0), kR, 1, m);
  ball.linear_velocity = Vec3(kV0, 0, 0);
  ball.lock_rotation = lock_rotation;
  s.ball = add_body(s.world, ball);
  return s;
}

WorldDef def_without(bool WorldDef::*feature) {
  WorldDef def = awake_def();
  def.*feature = false;
  return def;
}

/// Steps both worlds together and requires the two balls' states to be bit-identical after every
/// step: the two set-ups are the same physics and the engine must compute them the same way.
::testing::AssertionResult same_trajectory(World& a, BodyId ball_a, World& b, BodyId ball_b,
                                           int steps) {
  for (int i = 0; i < steps; ++i) {
    if (auto stepped = run(a, 1); !stepped) return stepped;
    if (auto stepped = run(b, 1); !stepped) return stepped;
    if (auto same = same_state(state_of(a, ball_a), state_of(b, ball_b)); !same)
      return same << " after step " << i + 1;
  }
  return ::testing::AssertionSuccess();
}

/// Speed of the ball's lowest point (the contact point on a floor): zero when it rolls.
double contact_point_speed(const BodyState& s) {
  const Vec3 slip = s.linear_velocity + s.angular_velocity.cross(Vec3(0, -s.radius, 0));
  return to_d(slip).norm();
}

// --- rotation ------------------------------------------------------------------------------

TEST(FeatureSwitch, WithoutRotationASlidingBallDeceleratesAtMuGToRest) {
  // No spin, so the contact point slides until the ball stops: the Coulomb impulse μ·m·g·h per
  // step takes v_n = v0 − n·μ·g·h, which stops after N = ⌊v0/(μgh)⌋ steps, having moved
  // x = h·Σ v_n = h·(N·v0 − μ·g·h·N(N+1)/2) (= v0²/(2μg) − v0·h/2 + O(h²)).
  Slide s = make_slide(def_without(&WorldDef::enable_rotation));
  const double h = double(kDt60), decel = double(kMu) * double(kGravity);
  ASSERT_TRUE(run(s.world, 30));
  // Measured (float): 2.0e-6 m/s off after 30 steps, 1.3e-6 m off at rest; 0 speed left.
  EXPECT_NEAR(state_of(s.world, s.ball).linear_velocity.x(), double(kV0) - 30 * decel * h, 1e-5)
      << "after 30 steps, still sliding";
  ASSERT_TRUE(run(s.world, 150));
  const BodyState end = state_of(s.world, s.ball);
  const double n = std::floor(double(kV0) / (decel * h));
  EXPECT_NEAR(end.position.x(), h * (n * double(kV0) - decel * h * n * (n + 1) / 2), 1e-5);
  EXPECT_LT(end.linear_velocity.norm(), Real(1e-5));
  EXPECT_EQ(end.angular_velocity, Vec3::Zero());
  EXPECT_TRUE(end.orientation.coeffs() == Quat::Identity().coeffs());
}

TEST(FeatureSwitch, WithRotationTheSameBallEndsRollingAtFiveSevenths) {
  // Friction spins the ball up while slowing it; it rolls once v = ω·r, after t = 2v0/(7μg)
  // (0.23 s), at v = 5/7·v0, and then keeps rolling.
  // Measured (float): 7e-7 m/s and 1.4e-6 rad/s off, contact point at rest.
  Slide s = make_slide(awake_def());
  ASSERT_TRUE(run(s.world, 180));
  const BodyState end = state_of(s.world, s.ball);
  EXPECT_NEAR(end.linear_velocity.x(), kV0 * 5 / 7, Real(1e-5));
  EXPECT_NEAR(end.angular_velocity.z(), -kV0 * 5 / 7 / kR, Real(2e-5));
  EXPECT_LT(contact_point_speed(end), 1e-5) << "rolls without slipping";
}

TEST(FeatureSwitch, WithoutRotationEveryBallSlidesAsIfLockedAgainstSpin) {
  // lock_rotation (infinite inertia) is the per-body form of enable_rotation = false.
  Slide off = make_slide(def_without(&WorldDef::enable_rotation));
  Slide locked = make_slide(awake_def(), material(0, kMu), /*lock_rotation=*/true);
  EXPECT_TRUE(same_trajectory(off.world, off.ball, locked.world, locked.ball, 120));
}

TEST(FeatureSwitch, WithoutRotationTorqueAndSpinDoNotTurnABall) {
  // A 1 kg solid ball of radius 0.5 m (I = 2/5·m·r² = 0.1 kg·m²) in space, spinning at 3 rad/s
  // about z, pushed by 0.2 N·m about x for one step. With rotation it gains ω_x = τ·h/I and turns
  // by ~3 rad about z in 1 s; without rotation it keeps the orientation it was given.
  const Quat start(Eigen::AngleAxis<Real>(Real(0.3), Vec3::UnitY()));
  for (const bool rotation : {true, false}) {
    WorldDef def = space_def();
    def.enable_rotation = rotation;
    World world = make_world(def);
    BodyDef body = sphere_def(Vec3::Zero(), kR, 1);
    body.orientation = start;
    body.angular_velocity = Vec3(0, 0, 3);
    const BodyId ball = add_body(world, body);
    RICOCHET_ASSERT_OK(world.apply_torque(ball, Vec3(Real(0.2), 0, 0)));
    ASSERT_TRUE(run(world, 1));
    const BodyState after_push = state_of(world, ball);
    ASSERT_TRUE(run(world, 59));
    const BodyState end = state_of(world, ball);
    if (rotation) {
      EXPECT_NEAR(after_push.angular_velocity.x(), Real(0.2) * kDt60 / Real(0.1), Real(1e-5));
      // The torque acts before the first position update, so the ball turns by |ω|·1 s about
      // the constant ω. Explicit quaternion steps with renormalisation follow that to 6.2e-4 rad
      // (measured, float).
      const Vec3 w = after_push.angular_velocity;
      const Quat expected = Quat(Eigen::AngleAxis<Real>(w.norm(), w.normalized())) * start;
      EXPECT_LT(end.orientation.angularDistance(expected), Real(0.002));
    } else {
      EXPECT_EQ(after_push.angular_velocity.x(), 0) << "torque ignored";
      EXPECT_TRUE(end.orientation.coeffs() == start.normalized().coeffs()) << "orientation as set";
    }
  }
}

// --- friction ------------------------------------------------------------------------------

TEST(FeatureSwitch, WithoutFrictionASlidingBallKeepsItsSpeedAndNeverSpins) {
  Slide s = make_slide(def_without(&WorldDef::enable_friction));
  ASSERT_TRUE(run(s.world, 120));
  const BodyState end = state_of(s.world, s.ball);
  // Measured (float): speed exact to 1e-7, position 4.8e-6 m off.
  EXPECT_NEAR(end.linear_velocity.x(), kV0, Real(1e-5));
  EXPECT_NEAR(end.position.x(), kV0 * 2, Real(5e-5)) << "2 s at v0";
  EXPECT_EQ(end.angular_velocity, Vec3::Zero());
}

TEST(FeatureSwitch, WithoutFrictionABallSlidesLikeOneOnAFrictionlessFloor) {
  Slide off = make_slide(def_without(&WorldDef::enable_friction));
  Slide frictionless = make_slide(awake_def(), material(0, 0));
  EXPECT_TRUE(same_trajectory(off.world, off.ball, frictionless.world, frictionless.ball, 120));
}

/// A ball released at rest on a 30° slope (normal tilted about z), both of material m: its
/// speed along the slope after 1 s, and its spin.
struct SlopeRun {
  double speed = 0;  ///< m/s, along the slope
  double spin = 0;   ///< rad/s, |ω|
  double slip = 0;   ///< m/s, speed of the contact point
};

SlopeRun roll_down_slope(const WorldDef& def, const Material& m) {
  const Real angle = Real(std::numbers::pi / 6);
  const Vec3 normal(-std::sin(angle), std::cos(angle), 0);
  World world = make_world(def);
  add_plane(world, normal, 0, m);
  const BodyId ball = add_sphere(world, normal * kR, kR, 1, m);
  run_or_throw(world, 60);
  const BodyState s = state_of(world, ball);
  const Vec3 slip = s.linear_velocity + s.angular_velocity.cross(-normal * kR);
  return {to_d(s.linear_velocity).norm(), to_d(s.angular_velocity).norm(), to_d(slip).norm()};
}

TEST(FeatureSwitch, OnASlopeWithoutFrictionABallSlidesAtGSinThetaAndWithFrictionRolls) {
  // Frictionless: a = g·sin θ, no spin. With μ = 0.5 > 2/7·tan θ (0.16) it rolls without
  // slipping: a = 5/7·g·sin θ. After 1 s at θ = 30°: 4.905 and 3.504 m/s. Measured (float):
  // 1.6e-6 and 1.0e-6 m/s off, spin 1.6e-6 rad/s off, slip 2.7e-7 m/s.
  const double g_sin = double(kGravity) * 0.5;
  const SlopeRun sliding =
      roll_down_slope(def_without(&WorldDef::enable_friction), material(0, kMu));
  EXPECT_NEAR(sliding.speed, g_sin, 1e-5);
  EXPECT_EQ(sliding.spin, 0);
  const SlopeRun rolling = roll_down_slope(awake_def(), material(0, kMu));
  EXPECT_NEAR(rolling.speed, g_sin * 5 / 7, 1e-5);
  EXPECT_NEAR(rolling.spin, g_sin * 5 / 7 / double(kR), 2e-5);
  EXPECT_LT(rolling.slip, 1e-5);
}

// --- rolling resistance --------------------------------------------------------------------

constexpr Real kRolling = Real(0.05);  ///< rolling resistance of ball and floor

TEST(FeatureSwitch, RollingResistanceSlowsTheSpinUpAndThenTheRollingBall) {
  // The resisting torque c·r·m·g opposes the spin from the start. Sliding: v = v0 − μ·g·t and
  // ω·r = (μ − c)·g·t·m·r²/I = 5/2·(μ − c)·g·t, so it rolls from t1 = v0 / ((7/2·μ − 5/2·c)·g)
  // (0.251 s) at v1 = v0 − μ·g·t1 (2.769 m/s); rolling, friction keeps v = ω·r and
  // a = −c·g / (1 + I/(m·r²)) = −5/7·c·g. Without the switch it rolls on at 5/7·v0 from
  // 2v0/(7μg). Measured (float): 6.9e-6 and 8e-7 m/s off, contact point at rest.
  const Material m = material(0, kMu, kRolling);
  Slide on = make_slide(awake_def(), m);
  Slide off = make_slide(def_without(&WorldDef::enable_rolling_resistance), m);
  ASSERT_TRUE(run(on.world, 180));
  ASSERT_TRUE(run(off.world, 180));
  const double t = 3.0, g = double(kGravity), mu = double(kMu), c = double(kRolling);
  const double t1 = double(kV0) / ((3.5 * mu - 2.5 * c) * g);
  const double v1 = double(kV0) - mu * g * t1;
  const BodyState with = state_of(on.world, on.ball);
  EXPECT_NEAR(with.linear_velocity.x(), v1 - 5.0 / 7 * c * g * (t - t1), 5e-5);
  EXPECT_LT(contact_point_speed(with), 1e-5) << "still rolling, not sliding";
  EXPECT_NEAR(state_of(off.world, off.ball).linear_velocity.x(), double(kV0) * 5 / 7, 1e-5);
}

TEST(FeatureSwitch, WithoutRollingResistanceABallRollsLikeOneWithNone) {
  Slide off =
      make_slide(def_without(&WorldDef::enable_rolling_resistance), material(0, kMu, kRolling));
  Slide none = make_slide(awake_def(), material(0, kMu, 0));
  EXPECT_TRUE(same_trajectory(off.world, off.ball, none.world, none.ball, 240));
}

// --- restitution ---------------------------------------------------------------------------

/// A ball of restitution e dropped from 2 m (bottom above the floor) onto a floor of the same
/// material.
struct Drop {
  World world;
  BodyId ball;
};

constexpr Real kDropHeight = 2;  ///< m

Drop make_drop(const WorldDef& def, Real e) {
  const Material m = material(e, kMu);
  Drop d{make_world(def), {}};
  add_floor(d.world, 0, m);
  d.ball = add_sphere(d.world, Vec3(0, kDropHeight + kR, 0), kR, 1, m);
  return d;
}

/// Highest bottom height above the floor after the first impact, within 2 s.
double rebound_apex(Drop& d) {
  double apex = 0;
  bool hit = false;
  for (int i = 0; i < 120; ++i) {
    run_or_throw(d.world, 1);
    const BodyState s = state_of(d.world, d.ball);
    hit = hit || s.linear_velocity.y() > 0;
    if (hit) apex = std::max(apex, double(s.position.y() - kR));
  }
  return apex;
}

TEST(FeatureSwitch, RestitutionReboundsToHESquaredAndSwitchedOffNothingBounces) {
  // On: the apex is h·e² (1.62 m for e = 0.9), less at most the g·dt²/8 the 60 Hz sampling can
  // miss (3.4e-4 m). Off: the ball stops on the floor and never moves up. Measured (float):
  // 4.4e-5 m below h·e²; switched off, no upward speed after the impact at all.
  const Real e = Real(0.9);
  Drop on = make_drop(awake_def(), e);
  const double sampling = double(kGravity) * double(kDt60) * double(kDt60) / 8;
  EXPECT_NEAR(rebound_apex(on), double(kDropHeight) * double(e * e), 1e-4 + sampling);
  Drop off = make_drop(def_without(&WorldDef::enable_restitution), e);
  EXPECT_LT(rebound_apex(off), 1e-4);
}

TEST(FeatureSwitch, WithoutRestitutionABallLandsLikeOneWithNone) {
  Drop off = make_drop(def_without(&WorldDef::enable_restitution), Real(0.9));
  Drop none = make_drop(awake_def(), 0);
  EXPECT_TRUE(same_trajectory(off.world, off.ball, none.world, none.ball, 120));
}

}  // namespace
}  // namespace ricochet::physics::test::feature_switch_test
