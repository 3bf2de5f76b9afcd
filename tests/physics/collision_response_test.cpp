// Sphere–sphere impacts against the 1-D impact laws, for every position-correction scheme.
//
// Gravity is zero, friction is zero and all approach speeds exceed restitution_threshold (1 m/s),
// so a head-on impact of masses m1, m2 with velocities u1, u2 and restitution e must give
//   v1 = (m1·u1 + m2·u2 − m2·e·(u1 − u2)) / (m1 + m2)
//   v2 = (m1·u1 + m2·u2 + m1·e·(u1 − u2)) / (m1 + m2)
// e = 1 with equal masses exchanges the velocities; e = 0 gives the common velocity.

#include "test_util.h"

namespace ricochet::physics::test::collision_response_test {
namespace {

struct HeadOn {
  Real m1, u1, m2, u2, e;
};

struct HeadOnResult {
  BodyState a, b;
  double max_momentum_error = 0;  ///< over every step, |p(t) − p(0)| (x component)
  double max_transverse = 0;      ///< largest |v_y|, |v_z|, |ω| seen
};

/// Two spheres of radius 0.5 on the x axis, 2 m apart centre to centre (1 m gap), closing.
HeadOnResult run_head_on(const HeadOn& c, PositionCorrection correction) {
  const WorldDef def = with_correction(space_def(), correction);
  World world = make_world(def);
  BodyDef da = sphere_def(Vec3(-1, 0, 0), Real(0.5), c.m1, material(c.e, 0));
  da.linear_velocity = Vec3(c.u1, 0, 0);
  BodyDef db = sphere_def(Vec3(1, 0, 0), Real(0.5), c.m2, material(c.e, 0));
  db.linear_velocity = Vec3(c.u2, 0, 0);
  const BodyId a = add_body(world, da);
  const BodyId b = add_body(world, db);

  HeadOnResult r;
  const double p0 = double(c.m1) * double(c.u1) + double(c.m2) * double(c.u2);
  for (int i = 0; i < 90; ++i) {  // 1.5 s; impact by t = 1 / |u1 − u2| ≤ 0.25 s here
    run_or_throw(world, 1);
    r.a = state_of(world, a);
    r.b = state_of(world, b);
    const double p = double(c.m1) * double(r.a.linear_velocity.x()) +
                     double(c.m2) * double(r.b.linear_velocity.x());
    r.max_momentum_error = std::max(r.max_momentum_error, std::abs(p - p0));
    for (const BodyState* s : {&r.a, &r.b}) {
      r.max_transverse =
          std::max({r.max_transverse, std::abs(double(s->linear_velocity.y())),
                    std::abs(double(s->linear_velocity.z())), double(s->angular_velocity.norm())});
    }
  }
  return r;
}

class CollisionResponseTest : public ::testing::TestWithParam<PositionCorrection> {
 protected:
  void check_head_on(const HeadOn& c) {
    const HeadOnResult r = run_head_on(c, GetParam());
    const double m1 = c.m1, m2 = c.m2, u1 = c.u1, u2 = c.u2, e = c.e;
    const double v1 = (m1 * u1 + m2 * u2 - m2 * e * (u1 - u2)) / (m1 + m2);
    const double v2 = (m1 * u1 + m2 * u2 + m1 * e * (u1 - u2)) / (m1 + m2);
    // Velocities: the impact law is exact for a single contact; 1% of the closing speed allows
    // for a solver that resolves the impact over a couple of iterations/steps or leaves a little
    // position-correction velocity, and is far below the difference between e = 0 and e = 1.
    const double tol = 0.01 * std::abs(u1 - u2);
    EXPECT_NEAR(r.a.linear_velocity.x(), v1, tol) << correction_name(GetParam());
    EXPECT_NEAR(r.b.linear_velocity.x(), v2, tol) << correction_name(GetParam());
    // Momentum: equal and opposite impulses conserve it up to rounding. Allow ~1000 roundings of
    // relative size eps on the momentum scale Σ m|u| (float: ~1e-3 kg·m/s for these cases).
    const double scale = std::abs(m1 * u1) + std::abs(m2 * u2);
    EXPECT_LE(r.max_momentum_error, 1000.0 * static_cast<double>(kEps) * scale)
        << correction_name(GetParam());
    // A head-on frictionless impact on the x axis has no reason to create y/z motion or spin.
    EXPECT_LT(r.max_transverse, 1e-4) << correction_name(GetParam());
    // They ended apart (or together for e = 0), never interpenetrating by more than the slop.
    EXPECT_GE(r.b.position.x() - r.a.position.x(), 1.0 - 0.01) << correction_name(GetParam());
  }
};

TEST_P(CollisionResponseTest, ElasticEqualMassesExchangeVelocities) {
  check_head_on({1, 2, 1, -2, 1});
}

TEST_P(CollisionResponseTest, ElasticOneMovingOneAtRestEqualMasses) {
  // Newton's cradle: the mover stops dead, the target leaves with its velocity.
  check_head_on({1, 3, 1, 0, 1});
}

TEST_P(CollisionResponseTest, ElasticUnequalMasses) {
  // m1 = 1 at 4 m/s onto m2 = 3 at rest: v1 = −2, v2 = +2.
  check_head_on({1, 4, 3, 0, 1});
}

TEST_P(CollisionResponseTest, InelasticGivesCommonVelocity) {
  // e = 0: both move at p / (m1 + m2) = 4 / 4 = 1 m/s.
  check_head_on({1, 4, 3, 0, 0});
}

TEST_P(CollisionResponseTest, InelasticEqualAndOppositeStops) {
  check_head_on({2, 2, 2, -2, 0});
}

TEST_P(CollisionResponseTest, PartialRestitution) {
  check_head_on({1, 3, 2, -1, Real(0.5)});
}

TEST_P(CollisionResponseTest, RestitutionCombinesAsMaximum) {
  // Material says restitution takes the larger value: e = 1 against e = 0 is elastic.
  const WorldDef def = with_correction(space_def(), GetParam());
  World world = make_world(def);
  BodyDef da = sphere_def(Vec3(-1, 0, 0), Real(0.5), 1, material(1, 0));
  da.linear_velocity = Vec3(2, 0, 0);
  BodyDef db = sphere_def(Vec3(1, 0, 0), Real(0.5), 1, material(0, 0));
  db.linear_velocity = Vec3(-2, 0, 0);
  const BodyId a = add_body(world, da);
  const BodyId b = add_body(world, db);
  ASSERT_TRUE(run(world, 60));
  EXPECT_NEAR(state_of(world, a).linear_velocity.x(), -2, 0.04);
  EXPECT_NEAR(state_of(world, b).linear_velocity.x(), 2, 0.04);
}

TEST_P(CollisionResponseTest, GlancingElasticEqualMassesLeaveAtRightAngles) {
  // Equal masses, elastic, frictionless, target at rest: whatever the contact normal turns out to
  // be, kinetic energy and momentum conservation force the outgoing velocities to be
  // perpendicular. This holds even if the normal is taken a step early, so it is robust to
  // discretisation. Impact parameter 0.5 m (30° normal).
  const WorldDef def = with_correction(space_def(), GetParam());
  World world = make_world(def);
  BodyDef da = sphere_def(Vec3(-2, Real(0.5), 0), Real(0.5), 1, material(1, 0));
  da.linear_velocity = Vec3(3, 0, 0);
  const BodyId a = add_body(world, da);
  const BodyId b = add_body(world, sphere_def(Vec3(0, 0, 0), Real(0.5), 1, material(1, 0)));
  ASSERT_TRUE(run(world, 60));
  const Eigen::Vector3d va = to_d(state_of(world, a).linear_velocity);
  const Eigen::Vector3d vb = to_d(state_of(world, b).linear_velocity);
  ASSERT_GT(vb.norm(), 0.5) << "no collision happened";
  // Energy within 1% (same allowance as the head-on cases), momentum to rounding.
  EXPECT_NEAR(va.squaredNorm() + vb.squaredNorm(), 9.0, 0.09);
  EXPECT_NEAR((va + vb - Eigen::Vector3d(3, 0, 0)).norm(), 0.0, 1e-3);
  // Perpendicular: |va·vb| small compared with |v0|² = 9 (1%).
  EXPECT_NEAR(va.dot(vb), 0.0, 0.09);
  // Without friction the struck sphere moves along the line of centres at impact: down-right.
  EXPECT_GT(vb.x(), 0);
  EXPECT_LT(vb.y(), 0);
  EXPECT_LT(state_of(world, b).angular_velocity.norm(), 1e-4);
}

TEST_P(CollisionResponseTest, KinematicBodyPushesAndIsNotPushed) {
  const WorldDef def = with_correction(space_def(), GetParam());
  World world = make_world(def);
  BodyDef dk = sphere_def(Vec3(-2, 0, 0), Real(0.5), 1, material(0, 0));
  dk.type = BodyType::Kinematic;
  dk.linear_velocity = Vec3(1, 0, 0);
  const BodyId kin = add_body(world, dk);
  const BodyId dyn = add_sphere(world, Vec3(0, 0, 0), Real(0.5), 1, material(0, 0));
  const int steps = 150;  // 2.5 s: the kinematic sphere reaches the dynamic one at t = 1 s
  ASSERT_TRUE(run(world, steps));
  const BodyState k = state_of(world, kin);
  const BodyState d = state_of(world, dyn);
  // The kinematic body follows its velocity exactly (rounding only).
  EXPECT_EQ(k.linear_velocity, Vec3(1, 0, 0));
  EXPECT_NEAR(k.position.x(), -2.0 + steps * double(kDt60), 1e-4);
  // The dynamic body was pushed ahead (e = 0: it moves with the pusher, 1 m/s, within 2%) and not
  // overlapped by more than the linear slop. Baumgarte is documented to add energy when it
  // corrects penetration, so there it may leave up to 10% faster than the pusher.
  EXPECT_GE(d.linear_velocity.x(), 0.98);
  EXPECT_LE(d.linear_velocity.x(), GetParam() == PositionCorrection::Baumgarte ? 1.1 : 1.02);
  EXPECT_GE(d.position.x() - k.position.x(), 1.0 - def.linear_slop - 1e-3);
}

TEST_P(CollisionResponseTest, NonMatchingFiltersPassThrough) {
  // A's layer is not in B's mask (and vice versa): no contact, velocities untouched.
  const WorldDef def = with_correction(space_def(), GetParam());
  World world = make_world(def);
  BodyDef da = sphere_def(Vec3(-1, 0, 0));
  da.linear_velocity = Vec3(2, 0, 0);
  da.filter.layer = 1;
  da.filter.mask = 1;
  BodyDef db = sphere_def(Vec3(1, 0, 0));
  db.linear_velocity = Vec3(-2, 0, 0);
  db.filter.layer = 2;
  db.filter.mask = 0xFFFFFFFFu;  // B would accept A, but A does not accept B: still no contact
  const BodyId a = add_body(world, da);
  const BodyId b = add_body(world, db);
  ASSERT_TRUE(run(world, 60));
  EXPECT_EQ(state_of(world, a).linear_velocity, Vec3(2, 0, 0));
  EXPECT_EQ(state_of(world, b).linear_velocity, Vec3(-2, 0, 0));
  EXPECT_GT(state_of(world, a).position.x(), state_of(world, b).position.x());
}

INSTANTIATE_TEST_SUITE_P(AllCorrections, CollisionResponseTest,
                         ::testing::ValuesIn(kAllCorrections),
                         [](const ::testing::TestParamInfo<PositionCorrection>& info) {
                           return std::string(correction_name(info.param));
                         });

}  // namespace
}  // namespace ricochet::physics::test::collision_response_test
