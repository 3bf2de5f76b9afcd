// The World API itself: creation, handles, body state as created, the direct setters, forces,
// torques and impulses against Newton's laws, counts, moves and the profile.

#include "test_util.h"

namespace ricochet::physics::test::world_api_test {
namespace {

TEST(WorldApi, EmptyWorld) {
  WorldDef def;
  def.iterations = 7;
  def.gravity = Vec3(0, -3, 0);
  World world = make_world(def);
  EXPECT_EQ(world.body_count(), 0u);
  EXPECT_EQ(world.shape_count(), 0u);
  EXPECT_EQ(world.step_count(), 0u);
  EXPECT_EQ(world.definition().iterations, 7);
  EXPECT_EQ(world.definition().gravity, Vec3(0, -3, 0));
  RICOCHET_ASSERT_OK(world.step(kDt60));
  EXPECT_EQ(world.step_count(), 1u);
  EXPECT_TRUE(world.contact_begin_events().empty());
  EXPECT_TRUE(world.contact_end_events().empty());
  EXPECT_TRUE(world.contact_impulse_events().empty());
  EXPECT_TRUE(world.nonfinite_events().empty());
}

TEST(WorldApi, BodyStateReflectsTheDefinition) {
  World world = make_world();
  BodyDef def;
  def.position = Vec3(1, 2, 3);
  def.orientation = Quat(Eigen::AngleAxis<Real>(Real(0.3), Vec3(0, 1, 0)));
  def.linear_velocity = Vec3(4, 5, 6);
  def.angular_velocity = Vec3(Real(0.1), Real(0.2), Real(0.3));
  def.radius = Real(0.25);
  def.mass = 4;
  def.user_data = 0xDEADBEEFCAFEull;
  const BodyId id = add_body(world, def);
  EXPECT_FALSE(id.is_null());
  EXPECT_TRUE(world.is_valid(id));
  EXPECT_EQ(world.body_count(), 1u);

  const BodyState s = state_of(world, id);
  EXPECT_EQ(s.type, BodyType::Dynamic);
  EXPECT_EQ(s.position, def.position);
  EXPECT_TRUE(s.orientation.isApprox(def.orientation, Real(1e-6)));
  EXPECT_EQ(s.linear_velocity, def.linear_velocity);
  EXPECT_EQ(s.angular_velocity, def.angular_velocity);
  EXPECT_EQ(s.radius, def.radius);
  EXPECT_EQ(s.user_data, def.user_data);
  EXPECT_FALSE(s.sleeping);
  EXPECT_FALSE(s.frozen);
  EXPECT_TRUE(s.force.isZero());
  EXPECT_TRUE(s.torque.isZero());
  EXPECT_NEAR(s.inverse_mass, 0.25, 1e-7);
  // Solid sphere: I = 2/5·m·r² = 0.1 kg·m², isotropic.
  const Mat3 expected = Mat3::Identity() * Real(1 / 0.1);
  EXPECT_TRUE(s.inverse_inertia_world.isApprox(expected, Real(1e-5))) << s.inverse_inertia_world;
}

TEST(WorldApi, InertiaModels) {
  World world = make_world();
  BodyDef hollow = sphere_def(Vec3::Zero(), Real(0.5), 3);
  hollow.inertia = InertiaModel::HollowSphere;
  BodyDef locked = sphere_def(Vec3(3, 0, 0), Real(0.5), 3);
  locked.lock_rotation = true;
  BodyDef kinematic = sphere_def(Vec3(6, 0, 0), Real(0.5), 3);
  kinematic.type = BodyType::Kinematic;
  const BodyState h = state_of(world, add_body(world, hollow));
  const BodyState l = state_of(world, add_body(world, locked));
  const BodyState k = state_of(world, add_body(world, kinematic));
  // Hollow: I = 2/3·m·r² = 0.5 kg·m².
  EXPECT_TRUE(h.inverse_inertia_world.isApprox(Mat3::Identity() * Real(2), Real(1e-5)));
  EXPECT_TRUE(l.inverse_inertia_world.isZero());
  EXPECT_NEAR(l.inverse_mass, 1.0 / 3.0, 1e-6);
  EXPECT_EQ(k.type, BodyType::Kinematic);
  EXPECT_EQ(k.inverse_mass, 0);
  EXPECT_TRUE(k.inverse_inertia_world.isZero());
}

TEST(WorldApi, DestroyInvalidatesOnlyThatHandle) {
  World world = make_world();
  const BodyId a = add_sphere(world, Vec3(0, 0, 0));
  const BodyId b = add_sphere(world, Vec3(2, 0, 0));
  RICOCHET_ASSERT_OK(world.destroy_body(a));
  EXPECT_FALSE(world.is_valid(a));
  EXPECT_TRUE(world.is_valid(b));
  EXPECT_EQ(world.body_count(), 1u);
  const BodyId c = add_sphere(world, Vec3(4, 0, 0));
  EXPECT_FALSE(c == a) << "a reused slot must get a new generation";
  EXPECT_FALSE(world.is_valid(a));
  EXPECT_EQ(state_of(world, c).position, Vec3(4, 0, 0));
}

TEST(WorldApi, SettersTakeEffectImmediately) {
  World world = make_world();
  const BodyId id = add_sphere(world, Vec3::Zero());
  const Quat q(Eigen::AngleAxis<Real>(Real(1), Vec3(1, 0, 0)));
  RICOCHET_ASSERT_OK(world.set_transform(id, Vec3(1, 2, 3), q));
  RICOCHET_ASSERT_OK(world.set_linear_velocity(id, Vec3(-1, 0, 2)));
  RICOCHET_ASSERT_OK(world.set_angular_velocity(id, Vec3(0, 3, 0)));
  const BodyState s = state_of(world, id);
  EXPECT_EQ(s.position, Vec3(1, 2, 3));
  EXPECT_TRUE(s.orientation.isApprox(q, Real(1e-6)));
  EXPECT_EQ(s.linear_velocity, Vec3(-1, 0, 2));
  EXPECT_EQ(s.angular_velocity, Vec3(0, 3, 0));
}

TEST(WorldApi, ForceActsForOneStep) {
  // F = m·a for exactly one step: Δv = F·dt/m, then nothing more (zero gravity).
  World world = make_world(space_def());
  const BodyId id = add_sphere(world, Vec3::Zero(), Real(0.5), 2);
  RICOCHET_ASSERT_OK(world.apply_force(id, Vec3(6, 0, 0)));
  RICOCHET_ASSERT_OK(world.apply_force(id, Vec3(0, 0, -2)));  // forces accumulate
  EXPECT_TRUE(near(state_of(world, id).force, Vec3(6, 0, -2), 1e-6));
  ASSERT_TRUE(run(world, 1));
  BodyState s = state_of(world, id);
  const double dt = kDt60;
  EXPECT_NEAR(s.linear_velocity.x(), 6 * dt / 2, 1e-6);
  EXPECT_NEAR(s.linear_velocity.z(), -2 * dt / 2, 1e-6);
  EXPECT_TRUE(s.force.isZero()) << "the accumulator is cleared by the step";
  ASSERT_TRUE(run(world, 10));
  s = state_of(world, id);
  EXPECT_NEAR(s.linear_velocity.x(), 6 * dt / 2, 1e-6) << "force applied for one step only";
}

TEST(WorldApi, TorqueActsForOneStep) {
  // Δω = I⁻¹·τ·dt with I = 2/5·m·r² = 0.2 kg·m² (m = 2, r = 0.5).
  World world = make_world(space_def());
  const BodyId id = add_sphere(world, Vec3::Zero(), Real(0.5), 2);
  RICOCHET_ASSERT_OK(world.apply_torque(id, Vec3(0, 0, 4)));
  EXPECT_TRUE(near(state_of(world, id).torque, Vec3(0, 0, 4), 1e-6));
  ASSERT_TRUE(run(world, 5));
  const BodyState s = state_of(world, id);
  EXPECT_NEAR(s.angular_velocity.z(), 4 * double(kDt60) / 0.2, 1e-5);
  EXPECT_TRUE(s.torque.isZero());
  EXPECT_TRUE(s.linear_velocity.isZero());
  // The orientation advanced about z by ω·(steps − 1 or steps)·dt: only check the axis and sign.
  const Eigen::AngleAxis<Real> aa(s.orientation);
  EXPECT_GT(std::abs(aa.angle()), 0);
  EXPECT_NEAR(std::abs(aa.axis().z()), 1.0, 1e-4);
}

TEST(WorldApi, ImpulseChangesVelocityImmediately) {
  World world = make_world(space_def());
  const BodyId id = add_sphere(world, Vec3(1, 0, 0), Real(0.5), 2);
  // At the centre: Δv = J/m, no spin.
  RICOCHET_ASSERT_OK(world.apply_impulse(id, Vec3(4, 0, 0), Vec3(1, 0, 0)));
  BodyState s = state_of(world, id);
  EXPECT_TRUE(near(s.linear_velocity, Vec3(2, 0, 0), 1e-6));
  EXPECT_TRUE(near(s.angular_velocity, Vec3::Zero(), 1e-6));
  // At the top of the sphere, pushing +x: Δv = J/m, Δω = I⁻¹·(r × J) = 5·((0,0.5,0) × (2,0,0))
  // = 5·(0, 0, −1) = (0, 0, −5).
  RICOCHET_ASSERT_OK(world.apply_impulse(id, Vec3(2, 0, 0), Vec3(1, Real(0.5), 0)));
  s = state_of(world, id);
  EXPECT_TRUE(near(s.linear_velocity, Vec3(3, 0, 0), 1e-6));
  EXPECT_TRUE(near(s.angular_velocity, Vec3(0, 0, -5), 1e-5));
}

TEST(WorldApi, ImpulseOnKinematicOrLockedBody) {
  World world = make_world(space_def());
  BodyDef kin = sphere_def(Vec3::Zero());
  kin.type = BodyType::Kinematic;
  const BodyId k = add_body(world, kin);
  // Whether this is an error or a no-op is not specified; either way nothing may move.
  const Status pushed = world.apply_impulse(k, Vec3(5, 0, 0), Vec3(0, Real(0.5), 0));
  if (!pushed.ok()) {
    EXPECT_FALSE(pushed.error().message.empty());
  }
  EXPECT_TRUE(state_of(world, k).linear_velocity.isZero()) << "kinematic bodies are not pushed";
  EXPECT_TRUE(state_of(world, k).angular_velocity.isZero());
  BodyDef locked = sphere_def(Vec3(3, 0, 0));
  locked.lock_rotation = true;
  const BodyId l = add_body(world, locked);
  RICOCHET_ASSERT_OK(world.apply_impulse(l, Vec3(1, 0, 0), Vec3(3, Real(0.5), 0)));
  EXPECT_TRUE(near(state_of(world, l).linear_velocity, Vec3(1, 0, 0), 1e-6));
  EXPECT_TRUE(state_of(world, l).angular_velocity.isZero());
}

TEST(WorldApi, KinematicBodyIgnoresGravityAndFollowsItsVelocity) {
  World world = make_world();
  BodyDef def = sphere_def(Vec3(0, 5, 0));
  def.type = BodyType::Kinematic;
  def.linear_velocity = Vec3(1, 0, 0);
  const BodyId id = add_body(world, def);
  ASSERT_TRUE(run(world, 60));
  const BodyState s = state_of(world, id);
  EXPECT_EQ(s.linear_velocity, Vec3(1, 0, 0));
  EXPECT_TRUE(near(s.position, Vec3(1, 5, 0), 1e-5));
}

TEST(WorldApi, StaticShapesCountAndRemove) {
  World world = make_world();
  const ShapeId plane = add_floor(world);
  const ShapeId box = add_box(world, Vec3(0, 5, 0), Vec3::Ones());
  const ShapeId mesh = add_mesh(world, {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, 1)}, {0, 1, 2});
  EXPECT_EQ(world.shape_count(), 3u);
  EXPECT_FALSE(plane == box);
  EXPECT_FALSE(box == mesh);
  RICOCHET_ASSERT_OK(world.remove_shape(box));
  EXPECT_EQ(world.shape_count(), 2u);
  EXPECT_TRUE(fails_with(world.remove_shape(box), ErrorCode::InvalidHandle));
}

TEST(WorldApi, RemovingTheFloorLetsABodyFall) {
  World world = make_world();  // sleeping off
  const ShapeId floor = add_floor(world);
  const BodyId id = add_sphere(world, Vec3(0, Real(0.5), 0));
  ASSERT_TRUE(run(world, 30));
  EXPECT_NEAR(state_of(world, id).position.y(), 0.5, 1e-3);
  RICOCHET_ASSERT_OK(world.remove_shape(floor));
  ASSERT_TRUE(run(world, 30));
  EXPECT_LT(state_of(world, id).position.y(), -0.5) << "fell ½·g·t² ≈ 1.2 m in 0.5 s";
}

TEST(WorldApi, MovedWorldKeepsItsState) {
  World world = make_world();
  add_floor(world);
  const BodyId id = add_sphere(world, Vec3(0, 3, 0));
  ASSERT_TRUE(run(world, 10));
  const std::uint64_t hash = world.state_hash();
  World moved = std::move(world);
  EXPECT_EQ(moved.state_hash(), hash);
  EXPECT_TRUE(moved.is_valid(id));
  World assigned = make_world();
  assigned = std::move(moved);
  EXPECT_EQ(assigned.state_hash(), hash);
  ASSERT_TRUE(run(assigned, 10));
  EXPECT_EQ(assigned.step_count(), 20u);
}

TEST(WorldApi, ProfileCountsBodiesAndContacts) {
  World world = make_world();  // sleeping off
  add_floor(world);
  for (int i = 0; i < 5; ++i) add_sphere(world, Vec3(Real(2 * i), Real(0.5), 0));
  ASSERT_TRUE(run(world, 3));
  const StepProfile& p = world.profile();
  EXPECT_EQ(p.bodies_awake, 5);
  EXPECT_GE(p.contacts, 5) << "each sphere rests on the floor";
  EXPECT_GE(p.total_ms, 0.0);
  for (double ms : {p.broad_phase_ms, p.narrow_phase_ms, p.solve_ms, p.integrate_ms,
                    p.continuous_ms, p.sleep_ms, p.events_ms}) {
    EXPECT_GE(ms, 0.0);
    EXPECT_LE(ms, p.total_ms + 1e-9);
  }
}

}  // namespace
}  // namespace ricochet::physics::test::world_api_test
