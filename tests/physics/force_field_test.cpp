// Force fields (springs, attractors) and the integrators that evaluate them, against closed forms:
// a spring is a harmonic oscillator, an attractor holds a circular orbit.

#include <numbers>

#include "test_util.h"

namespace ricochet::physics::test::force_field_test {
namespace {

constexpr Real kPi = std::numbers::pi_v<Real>;

WorldDef integrator_def(Integrator integrator) {
  WorldDef def = space_def();
  def.integrator = integrator;
  return def;
}

/// A 1 kg sphere on a 1 Hz spring (k = 4π² N/m) to the origin, released at x = amplitude.
struct Oscillator {
  World world;
  BodyId body;
};

Oscillator make_oscillator(Integrator integrator, Real amplitude = 1) {
  Oscillator o{make_world(integrator_def(integrator)), {}};
  o.body = add_sphere(o.world, Vec3(amplitude, 0, 0), Real(0.1), 1);
  SpringDef spring;
  spring.body = o.body;
  spring.stiffness = 4 * kPi * kPi;
  unwrap(o.world.add_spring(spring), "add_spring");
  return o;
}

/// Total energy of the 1 Hz oscillator, J.
Real oscillator_energy(const BodyState& s) {
  return Real(0.5) * s.linear_velocity.squaredNorm() +
         Real(0.5) * 4 * kPi * kPi * s.position.squaredNorm();
}

TEST(ForceField, Rk4FollowsTheHarmonicOscillatorClosely) {
  // x(t) = cos(2πt): after 2 s (two periods) the ball is back at x = 1.
  Oscillator rk4 = make_oscillator(Integrator::Rk4);
  Oscillator euler = make_oscillator(Integrator::SemiImplicitEuler);
  ASSERT_TRUE(run(rk4.world, 120));
  ASSERT_TRUE(run(euler.world, 120));
  const Real rk4_error = (state_of(rk4.world, rk4.body).position - Vec3(1, 0, 0)).norm();
  const Real euler_error = (state_of(euler.world, euler.body).position - Vec3(1, 0, 0)).norm();
  EXPECT_LT(rk4_error, Real(2e-4)) << "Rk4 error after two periods";
  EXPECT_LT(rk4_error * 10, euler_error) << "fourth order should beat first order by far";
}

TEST(ForceField, ExplicitEulerGainsEnergySymplecticAndRk4DoNot) {
  // Explicit Euler multiplies the oscillator's energy by (1 + ω²h²) per step; semi-implicit Euler
  // keeps it bounded (oscillating by ~ωh); RK4 loses a little, very slowly.
  Real final_energy[3] = {};
  Real worst_drift[3] = {};
  const Integrator integrators[3] = {Integrator::ExplicitEuler, Integrator::SemiImplicitEuler,
                                     Integrator::Rk4};
  const Real e0 = oscillator_energy(BodyState{.position = Vec3(1, 0, 0)});
  for (int i = 0; i < 3; ++i) {
    Oscillator o = make_oscillator(integrators[i]);
    for (int step = 0; step < 600; ++step) {
      ASSERT_TRUE(run(o.world, 1));
      const Real e = oscillator_energy(state_of(o.world, o.body));
      worst_drift[i] = std::max(worst_drift[i], std::abs(e - e0) / e0);
      final_energy[i] = e;
    }
  }
  const Real omega_h = 2 * kPi / 60;
  const Real explicit_growth = std::pow(1 + omega_h * omega_h, Real(600));
  EXPECT_NEAR(final_energy[0] / e0, explicit_growth, explicit_growth * Real(0.02))
      << "explicit Euler grows by (1 + ω²h²)^n";
  EXPECT_LT(worst_drift[1], Real(0.12)) << "semi-implicit Euler stays bounded (about ωh)";
  EXPECT_LT(worst_drift[2], Real(1e-3)) << "RK4 over 10 s";
}

TEST(ForceField, Rk4IsExactForConstantGravity) {
  // Free fall is a quadratic in t: RK4 integrates it without truncation error.
  World world = make_world([] {
    WorldDef def = awake_def();
    def.integrator = Integrator::Rk4;
    return def;
  }());
  const BodyId ball = add_sphere(world, Vec3(0, 100, 0));
  ASSERT_TRUE(run(world, 60));
  const Real expected = 100 - Real(0.5) * kGravity;
  EXPECT_NEAR(state_of(world, ball).position.y(), expected, 100 * 8 * kEps);
  EXPECT_NEAR(state_of(world, ball).linear_velocity.y(), -kGravity, 64 * kEps * kGravity);
}

TEST(ForceField, AttractorHoldsACircularOrbit) {
  // GM = 100 m³/s², r = 10 m: v = sqrt(GM/r) = sqrt(10) m/s, period 2π·r/v ≈ 19.87 s.
  const Real gm = 100, r = 10;
  const Real v = std::sqrt(gm / r);
  const Real period = 2 * kPi * r / v;
  World world = make_world(integrator_def(Integrator::Rk4));
  AttractorDef attractor;
  attractor.strength = gm;
  unwrap(world.add_attractor(attractor), "add_attractor");
  BodyDef def = sphere_def(Vec3(r, 0, 0), Real(0.1), 1);
  def.linear_velocity = Vec3(0, 0, v);
  const BodyId satellite = add_body(world, def);
  const int steps = static_cast<int>(std::lround(period * 120));
  Real max_radius_error = 0;
  for (int i = 0; i < steps; ++i) {
    ASSERT_TRUE(run(world, 1, Real(1) / 120));
    max_radius_error =
        std::max(max_radius_error, std::abs(state_of(world, satellite).position.norm() - r));
  }
  EXPECT_LT(max_radius_error, Real(1e-3) * r) << "the orbit stays circular";
  EXPECT_LT((state_of(world, satellite).position - Vec3(r, 0, 0)).norm(), Real(0.02) * r)
      << "back at the start after one period";
}

TEST(ForceField, AttractorPullsOnlyTheLayersInItsMask) {
  World world = make_world(integrator_def(Integrator::SemiImplicitEuler));
  AttractorDef attractor;
  attractor.strength = 10;
  attractor.mask = 0b10;
  unwrap(world.add_attractor(attractor), "add_attractor");
  BodyDef pulled = sphere_def(Vec3(5, 0, 0));
  pulled.filter.layer = 0b10;
  BodyDef ignored = sphere_def(Vec3(-5, 0, 0));
  ignored.filter.layer = 0b01;
  const BodyId a = add_body(world, pulled);
  const BodyId b = add_body(world, ignored);
  ASSERT_TRUE(run(world, 10));
  EXPECT_LT(state_of(world, a).position.x(), Real(5));
  EXPECT_EQ(state_of(world, b).position.x(), Real(-5));
}

TEST(ForceField, DampedSpringSettlesAtItsRestLength) {
  World world = make_world(awake_def());
  const BodyId ball = add_sphere(world, Vec3(0, -1, 0), Real(0.1), 2);
  SpringDef spring;
  spring.body = ball;
  spring.stiffness = 200;
  spring.rest_length = 1;
  spring.damping = 20;
  unwrap(world.add_spring(spring), "add_spring");
  ASSERT_TRUE(run(world, 600));
  // Hanging below the anchor: k·(L - 1) = m·g.
  const Real expected = -(1 + 2 * kGravity / 200);
  EXPECT_NEAR(state_of(world, ball).position.y(), expected, Real(1e-3));
  EXPECT_LT(state_of(world, ball).linear_velocity.norm(), Real(1e-3));
}

TEST(ForceField, SpringGoesWithItsBodyAndHandlesAreChecked) {
  World world = make_world(space_def());
  const BodyId ball = add_sphere(world, Vec3(1, 0, 0));
  SpringDef spring;
  spring.body = ball;
  spring.stiffness = 1;
  const ForceId id = unwrap(world.add_spring(spring), "add_spring");
  EXPECT_EQ(world.force_count(), 1u);
  check(world.destroy_body(ball), "destroy_body");
  EXPECT_EQ(world.force_count(), 0u);
  EXPECT_TRUE(fails_with(world.remove_force(id), ErrorCode::InvalidHandle));
  EXPECT_TRUE(fails_with(world.remove_force(ForceId{}), ErrorCode::InvalidHandle));
  EXPECT_TRUE(fails_with(world.add_spring(spring), ErrorCode::InvalidHandle)) << "dead body";
}

TEST(ForceField, InvalidDefinitionsAreRejected) {
  World world = make_world(space_def());
  const BodyId ball = add_sphere(world, Vec3(1, 0, 0));
  BodyDef kinematic_def = sphere_def(Vec3(3, 0, 0));
  kinematic_def.type = BodyType::Kinematic;
  const BodyId kinematic = add_body(world, kinematic_def);
  const auto spring = [&](auto&& edit) {
    SpringDef def;
    def.body = ball;
    def.stiffness = 1;
    edit(def);
    return world.add_spring(def);
  };
  EXPECT_TRUE(
      fails_with(spring([](SpringDef& d) { d.stiffness = 0; }), ErrorCode::InvalidArgument));
  EXPECT_TRUE(
      fails_with(spring([](SpringDef& d) { d.stiffness = kNaN; }), ErrorCode::InvalidArgument));
  EXPECT_TRUE(
      fails_with(spring([](SpringDef& d) { d.anchor.x() = kInf; }), ErrorCode::InvalidArgument));
  EXPECT_TRUE(
      fails_with(spring([](SpringDef& d) { d.rest_length = -1; }), ErrorCode::InvalidArgument));
  EXPECT_TRUE(fails_with(spring([](SpringDef& d) { d.damping = -1; }), ErrorCode::InvalidArgument));
  EXPECT_TRUE(
      fails_with(spring([&](SpringDef& d) { d.body = kinematic; }), ErrorCode::InvalidArgument));
  AttractorDef attractor;
  attractor.strength = 0;
  EXPECT_TRUE(fails_with(world.add_attractor(attractor), ErrorCode::InvalidArgument));
  attractor.strength = 1;
  attractor.min_distance = 0;
  EXPECT_TRUE(fails_with(world.add_attractor(attractor), ErrorCode::InvalidArgument));
  attractor.min_distance = 1;
  attractor.center.y() = kNaN;
  EXPECT_TRUE(fails_with(world.add_attractor(attractor), ErrorCode::InvalidArgument));
  EXPECT_EQ(world.force_count(), 0u) << "nothing was added";
}

TEST(ForceField, SaveRestoreCarriesFieldsBitExactly) {
  Oscillator o = make_oscillator(Integrator::Rk4);
  AttractorDef attractor;
  attractor.center = Vec3(0, 5, 0);
  attractor.strength = 3;
  unwrap(o.world.add_attractor(attractor), "add_attractor");
  ASSERT_TRUE(run(o.world, 10));
  const std::vector<std::uint8_t> image = o.world.save_state();
  const std::uint64_t hash_at_save = o.world.state_hash();
  ASSERT_TRUE(run(o.world, 30));
  const std::uint64_t hash_later = o.world.state_hash();

  World copy = make_world(integrator_def(Integrator::Rk4));
  check(copy.restore_state(image), "restore_state");
  EXPECT_EQ(copy.state_hash(), hash_at_save);
  EXPECT_EQ(copy.force_count(), 2u);
  ASSERT_TRUE(run(copy, 30));
  EXPECT_EQ(copy.state_hash(), hash_later) << "the restored fields act identically";
}

}  // namespace
}  // namespace ricochet::physics::test::force_field_test
