// Projectiles: exact ballistic flight, swept hits that never tunnel, hits on moving bodies by
// relative motion, filters, the shooter ignored, validation, and save/restore.

#include <optional>

#include "test_util.h"

namespace ricochet::physics::test::projectile_test {
namespace {

ProjectileDef bullet(const Vec3& position, const Vec3& velocity, Real radius = Real(0.01)) {
  ProjectileDef def;
  def.position = position;
  def.velocity = velocity;
  def.radius = radius;
  def.gravity_scale = 0;
  return def;
}

ProjectileId fire(World& world, const ProjectileDef& def) {
  return unwrap(world.create_projectile(def), "create_projectile");
}

/// Steps until the projectile is gone or `steps` ran; returns its hit, if any.
std::optional<ProjectileHitEvent> run_until_hit(World& world, ProjectileId id, int steps,
                                                Real dt = kDt60) {
  for (int i = 0; i < steps; ++i) {
    run_or_throw(world, 1, dt);
    for (const ProjectileHitEvent& e : world.projectile_hit_events()) {
      if (e.projectile == id) return e;
    }
  }
  return std::nullopt;
}

TEST(Projectile, FliesTheClosedFormUnderGravity) {
  World world = make_world(awake_def());  // gravity (0, -9.81, 0)
  ProjectileDef def = bullet(Vec3(0, 100, 0), Vec3(30, 40, 5));
  def.gravity_scale = 1;
  const ProjectileId id = fire(world, def);
  const int steps = 120;
  ASSERT_TRUE(run(world, steps));
  const double t = steps * double(kDt60);
  const Eigen::Vector3d g(0, -double(kGravity), 0);
  const Eigen::Vector3d expected = to_d(def.position) + to_d(def.velocity) * t + 0.5 * g * t * t;
  const ProjectileState s = unwrap(world.projectile_state(id), "projectile_state");
  // Exact per step; what is left is round-off of 120 additions at ~100 m.
  EXPECT_LT((to_d(s.position) - expected).norm(), 1e-3);
  EXPECT_LT((to_d(s.velocity) - (to_d(def.velocity) + g * t)).norm(), 1e-3);
}

TEST(Projectile, NeverPassesAThinWallAtAnySpeed) {
  for (const Real speed : {Real(100), Real(1000), Real(5000)}) {
    for (const Real dt : {Real(1) / 30, kDt60}) {
      World world = make_world(space_def());
      const ShapeId wall = add_box(world, Vec3(10, 0, 0), Vec3(Real(0.005), 5, 5));
      const ProjectileId id = fire(world, bullet(Vec3(0, Real(0.3), 0), Vec3(speed, 0, 0), 0));
      const auto hit = run_until_hit(world, id, 200, dt);
      ASSERT_TRUE(hit.has_value()) << speed << " m/s passed the 1 cm wall at dt " << dt;
      EXPECT_EQ(hit->target.shape, wall);
      EXPECT_NEAR(hit->point.x(), Real(9.995), Real(1e-3));
      EXPECT_NEAR(hit->normal.x(), -1, 1e-5);
      EXPECT_FALSE(world.is_valid(id)) << "a projectile is gone after its hit";
      EXPECT_EQ(world.projectile_count(), 0u);
    }
  }
}

TEST(Projectile, HitTimeAndVelocityAreThoseOfTheTouch) {
  World world = make_world(space_def());
  add_plane(world, -Vec3::UnitX(), -Real(7.5));  // solid beyond x = 7.5
  const ProjectileId id = fire(world, bullet(Vec3::Zero(), Vec3(300, 0, 0), Real(0.02)));
  const auto hit = run_until_hit(world, id, 10);
  ASSERT_TRUE(hit.has_value());
  // The surface of the bullet touches x = 7.5 at 7.48 m: 1 full step (5 m) plus 2.48/300 s.
  EXPECT_NEAR(hit->time, Real(2.48 / 300), Real(1e-5));
  EXPECT_NEAR(hit->point.x(), Real(7.5), Real(1e-4));
  EXPECT_NEAR(hit->velocity.x(), 300, Real(1e-3));
}

TEST(Projectile, HitsABodyThatCrossesItsPathDuringTheStep) {
  // The body starts below the bullet's line and ends above it within one step, never touching it
  // at either end: only a test along both moves sees the hit.
  World world = make_world(space_def());
  BodyDef runner = sphere_def(Vec3(5, -2, 0), Real(0.4), 80);
  runner.linear_velocity = Vec3(0, 240, 0);  // 4 m in a 1/60 s step
  const BodyId body = add_body(world, runner);
  const ProjectileId id = fire(world, bullet(Vec3(0, 0, 0), Vec3(600, 0, 0)));  // 10 m per step
  const auto hit = run_until_hit(world, id, 1);
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->target.body, body);
  // Both moves are linear: at the touch time t the centres are 0.41 m apart.
  const Real t = hit->time;
  const Vec3 bullet_at(600 * t, 0, 0);
  const Vec3 body_at(5, -2 + 240 * t, 0);
  EXPECT_NEAR((bullet_at - body_at).norm(), Real(0.41), Real(1e-3));
  EXPECT_EQ(state_of(world, body).linear_velocity, runner.linear_velocity)
      << "a projectile pushes nothing";
}

TEST(Projectile, MissesABodyThatLeftItsPathBeforeItArrived) {
  World world = make_world(space_def());
  BodyDef runner = sphere_def(Vec3(9, 0, 0), Real(0.4), 80);
  runner.linear_velocity = Vec3(0, 240, 0);  // gone from the line within 0.0017 s
  add_body(world, runner);
  const ProjectileId id = fire(world, bullet(Vec3(0, 0, 0), Vec3(600, 0, 0)));
  ASSERT_FALSE(run_until_hit(world, id, 1).has_value());
  EXPECT_TRUE(world.is_valid(id));
}

TEST(Projectile, IgnoresItsShooterAndFilteredLayers) {
  World world = make_world(space_def());
  const BodyId shooter = add_sphere(world, Vec3(0, 0, 0), Real(0.4));
  BodyDef ghost_def = sphere_def(Vec3(3, 0, 0), Real(0.4));
  ghost_def.filter = {1u << 5, 0xFFFFFFFFu};
  add_body(world, ghost_def);
  const BodyId target = add_sphere(world, Vec3(6, 0, 0), Real(0.4));
  ProjectileDef def = bullet(Vec3(-1, 0, 0), Vec3(300, 0, 0));  // starts behind the shooter
  def.ignore = shooter;
  def.filter = {1u << 2, ~(1u << 5)};  // does not hit layer 5
  const ProjectileId id = fire(world, def);
  const auto hit = run_until_hit(world, id, 5);
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->target.body, target);
}

TEST(Projectile, EarliestOfStaticAndBodyHitsWins) {
  World world = make_world(space_def());
  const BodyId near_body = add_sphere(world, Vec3(4, 0, 0), Real(0.5));
  add_box(world, Vec3(6, 0, 0), Vec3(Real(0.1), 2, 2));
  const ProjectileId id = fire(world, bullet(Vec3::Zero(), Vec3(600, 0, 0)));
  const auto hit = run_until_hit(world, id, 1);
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->target.body, near_body);
  EXPECT_TRUE(hit->target.shape.is_null());
}

TEST(Projectile, UserDataAndStateAreReported) {
  World world = make_world(space_def());
  ProjectileDef def = bullet(Vec3(1, 2, 3), Vec3(4, 5, 6));
  def.user_data = 0xfeedULL;
  const ProjectileId id = fire(world, def);
  const ProjectileState s = unwrap(world.projectile_state(id), "projectile_state");
  EXPECT_EQ(s.position, def.position);
  EXPECT_EQ(s.velocity, def.velocity);
  EXPECT_EQ(s.user_data, 0xfeedULL);
  RICOCHET_EXPECT_OK(world.destroy_projectile(id));
  EXPECT_TRUE(fails_with(world.destroy_projectile(id), ErrorCode::InvalidHandle));
  EXPECT_TRUE(fails_with(world.projectile_state(id), ErrorCode::InvalidHandle));
  // The slot is reused under a new generation; the old handle stays stale.
  const ProjectileId again = fire(world, def);
  EXPECT_EQ(again.index, id.index);
  EXPECT_NE(again.generation, id.generation);
  EXPECT_FALSE(world.is_valid(id));
}

TEST(Projectile, BadDefinitionsAreRejectedAndChangeNothing) {
  WorldDef wd = space_def();
  wd.max_projectiles = 2;
  World world = make_world(wd);
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  const Real inf = std::numeric_limits<Real>::infinity();
  const std::vector<ProjectileDef> bad = {
      bullet(Vec3(nan, 0, 0), Vec3::UnitX()),
      bullet(Vec3::Zero(), Vec3(0, inf, 0)),
      bullet(Vec3::Zero(), Vec3::UnitX(), -1),
      bullet(Vec3::Zero(), Vec3::UnitX(), nan),
      bullet(Vec3::Zero(), Vec3(2e4, 0, 0)),  // above max_linear_speed (1e4 m/s)
      [inf] {
        ProjectileDef d = bullet(Vec3::Zero(), Vec3::UnitX());
        d.gravity_scale = inf;
        return d;
      }(),
  };
  for (const ProjectileDef& def : bad)
    EXPECT_TRUE(fails_with(world.create_projectile(def), ErrorCode::InvalidArgument));
  EXPECT_EQ(world.projectile_count(), 0u);
  fire(world, bullet(Vec3::Zero(), Vec3::UnitX()));
  fire(world, bullet(Vec3::Zero(), Vec3::UnitX()));
  EXPECT_TRUE(fails_with(world.create_projectile(bullet(Vec3::Zero(), Vec3::UnitX())),
                         ErrorCode::CapacityExceeded));
  EXPECT_EQ(world.projectile_count(), 2u);
}

TEST(Projectile, SaveRestoreReplaysProjectilesBitExactly) {
  World world = make_world(awake_def());
  add_floor(world);
  const BodyId body = add_sphere(world, Vec3(20, 1, 0), Real(0.5));
  for (int i = 0; i < 8; ++i) {
    ProjectileDef def = bullet(Vec3(0, Real(1 + 0.1 * i), 0), Vec3(Real(40 + i), 0, 0));
    def.gravity_scale = 1;
    fire(world, def);
  }
  ASSERT_TRUE(run(world, 5));
  const std::vector<std::uint8_t> image = world.save_state();
  const std::uint64_t hash_at_save = world.state_hash();
  ASSERT_TRUE(run(world, 60));
  const std::uint64_t hash_later = world.state_hash();
  const std::size_t hits_later = world.projectile_count();
  RICOCHET_ASSERT_OK(world.restore_state(image));
  EXPECT_EQ(world.state_hash(), hash_at_save);
  EXPECT_EQ(world.projectile_count(), 8u);
  ASSERT_TRUE(run(world, 60));
  EXPECT_EQ(world.state_hash(), hash_later);
  EXPECT_EQ(world.projectile_count(), hits_later);
  EXPECT_TRUE(world.is_valid(body));
}

// Found by the restore_state fuzzer: falling sped a projectile past max_linear_speed, and the
// world's own save image was then refused.
TEST(Projectile, FallingSpeedIsCappedAtMaxLinearSpeed) {
  World world = make_world(WorldDef{});
  ProjectileDef def;
  def.position = Vec3(0, 1000, 0);
  def.velocity = Vec3(0, -9990, 0);
  def.gravity_scale = 100;
  const ProjectileId id = unwrap(world.create_projectile(def), "create_projectile");
  ASSERT_TRUE(run(world, 60));
  ASSERT_TRUE(world.is_valid(id));
  const Real speed = unwrap(world.projectile_state(id), "projectile_state").velocity.norm();
  EXPECT_LE(speed, world.definition().max_linear_speed * Real(1 + 1e-6));
  EXPECT_GT(speed, world.definition().max_linear_speed * Real(0.999));
  World copy = make_world(WorldDef{});
  RICOCHET_EXPECT_OK(copy.restore_state(world.save_state()));
}

// Found by the fuzzer: a finite but absurd gravity scale flew a projectile to infinity.
TEST(Projectile, OneThatLeavesTheFiniteRangeIsRemoved) {
  World world = make_world(WorldDef{});
  ProjectileDef def;
  def.position = Vec3(0, 1, 0);
  def.gravity_scale = std::numeric_limits<Real>::max();  // times g overflows
  const ProjectileId id = unwrap(world.create_projectile(def), "create_projectile");
  ASSERT_TRUE(run(world, 1));
  EXPECT_FALSE(world.is_valid(id));
  EXPECT_EQ(world.projectile_count(), 0u);
  World copy = make_world(WorldDef{});
  RICOCHET_EXPECT_OK(copy.restore_state(world.save_state()));
}

}  // namespace
}  // namespace ricochet::physics::test::projectile_test
