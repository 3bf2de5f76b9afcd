// Ray casts, sphere casts and overlap queries against analytic intersections.
//
// Ray hits are closed-form (a division or a square root), so they must be exact to 1e-5 m: with
// coordinates below 10 m a float carries ~1e-6 m, and 1e-5 m leaves 10 ulp for the arithmetic.
// Sphere casts against boxes and triangles may be solved iteratively (conservative advancement
// stopping at some tolerance), so they get 1e-4 m, still 50x below linear_slop.
//
// Scenes have zero gravity and are stepped once before querying, so the queries see the
// broadphase of a stepped world whatever the implementation does with fresh bodies; the one test
// that queries without stepping says so in its name.

#include "test_util.h"

namespace ricochet::physics::test::ray_cast_test {
namespace {

constexpr double kRayTol = 1e-5;
constexpr double kCastTol = 1e-4;

World query_world() {
  return make_world(space_def());
}

void settle(World& world) {
  run_or_throw(world, 1);
}

bool is_shape(const ContactTarget& t, ShapeId id) {
  return t.shape == id && t.body.is_null();
}
bool is_body(const ContactTarget& t, BodyId id) {
  return t.body == id && t.shape.is_null();
}

::testing::AssertionResult hit_matches(const RayHit& hit, const Vec3& point, const Vec3& normal,
                                       double distance, double tol) {
  if (!near(hit.point, point, tol))
    return ::testing::AssertionFailure() << "point: " << near(hit.point, point, tol).message();
  if (!near(hit.normal, normal, tol))
    return ::testing::AssertionFailure() << "normal: " << near(hit.normal, normal, tol).message();
  if (std::abs(double(hit.distance) - distance) > tol) {
    return ::testing::AssertionFailure()
           << "distance " << hit.distance << ", expected " << distance;
  }
  return ::testing::AssertionSuccess();
}

TEST(RayCast, PlaneStraightDown) {
  World world = query_world();
  const ShapeId floor = add_floor(world);
  settle(world);
  RayHit hit;
  ASSERT_TRUE(world.ray_cast_closest(Vec3(1, 5, 2), Vec3(0, -1, 0), 10, {}, hit));
  EXPECT_TRUE(is_shape(hit.target, floor));
  EXPECT_TRUE(hit_matches(hit, Vec3(1, 0, 2), Vec3(0, 1, 0), 5, kRayTol));
  EXPECT_NEAR(hit.fraction, 0.5, kRayTol);
}

TEST(RayCast, PlaneOblique) {
  World world = query_world();
  add_floor(world);
  settle(world);
  RayHit hit;
  // Direction (3, −4, 0)/5 from (0, 4, 0): reaches y = 0 after 5 m at (3, 0, 0).
  ASSERT_TRUE(world.ray_cast_closest(Vec3(0, 4, 0), Vec3(Real(0.6), Real(-0.8), 0), 10, {}, hit));
  EXPECT_TRUE(hit_matches(hit, Vec3(3, 0, 0), Vec3(0, 1, 0), 5, kRayTol));
  EXPECT_NEAR(hit.fraction, 0.5, kRayTol);
}

TEST(RayCast, TiltedPlane) {
  // Plane x + y = √2 (unit normal (1, 1, 0)/√2, offset 1). From (5, 0, 0) along −x it is hit at
  // x = √2, 5 − √2 m away; the normal points back towards the caster. (The normal is passed
  // unit length: whether the offset is rescaled when a non-unit normal is normalised is not
  // specified.)
  World world = query_world();
  const double s2 = std::sqrt(2.0);
  const ShapeId plane = add_plane(world, Vec3(Real(1 / s2), Real(1 / s2), 0), 1);
  settle(world);
  RayHit hit;
  ASSERT_TRUE(world.ray_cast_closest(Vec3(5, 0, 0), Vec3(-1, 0, 0), 10, {}, hit));
  EXPECT_TRUE(is_shape(hit.target, plane));
  EXPECT_TRUE(
      hit_matches(hit, Vec3(Real(s2), 0, 0), Vec3(Real(1 / s2), Real(1 / s2), 0), 5 - s2, kRayTol));
}

TEST(RayCast, PlaneMisses) {
  World world = query_world();
  add_floor(world);
  settle(world);
  RayHit hit;
  EXPECT_FALSE(world.ray_cast_closest(Vec3(0, 1, 0), Vec3(1, 0, 0), 100, {}, hit)) << "parallel";
  EXPECT_FALSE(world.ray_cast_closest(Vec3(0, 1, 0), Vec3(0, 1, 0), 100, {}, hit)) << "away";
  EXPECT_FALSE(world.ray_cast_closest(Vec3(0, 5, 0), Vec3(0, -1, 0), Real(4.9), {}, hit))
      << "too short";
  EXPECT_TRUE(world.ray_cast_all(Vec3(0, 5, 0), Vec3(0, -1, 0), Real(4.9), {}).empty());
}

TEST(RayCast, NonUnitDirectionGivesTheSameHitPoint) {
  // The header says the direction need not be unit. Whether max_distance is then metres or a
  // multiple of |direction| is not pinned down, so only the hit point, normal and the distance
  // in metres (the same under both readings here) are checked, not the fraction.
  World world = query_world();
  add_floor(world);
  settle(world);
  RayHit hit;
  ASSERT_TRUE(world.ray_cast_closest(Vec3(1, 5, 2), Vec3(0, -2, 0), 10, {}, hit));
  EXPECT_TRUE(hit_matches(hit, Vec3(1, 0, 2), Vec3(0, 1, 0), 5, kRayTol));
}

TEST(RayCast, AxisAlignedBox) {
  World world = query_world();
  const ShapeId box = add_box(world, Vec3(0, 1, 0), Vec3(1, Real(0.5), 2));
  settle(world);
  RayHit hit;
  ASSERT_TRUE(world.ray_cast_closest(Vec3(-5, Real(1.2), Real(0.3)), Vec3(1, 0, 0), 10, {}, hit));
  EXPECT_TRUE(is_shape(hit.target, box));
  EXPECT_TRUE(hit_matches(hit, Vec3(-1, Real(1.2), Real(0.3)), Vec3(-1, 0, 0), 4, kRayTol));
  EXPECT_NEAR(hit.fraction, 0.4, kRayTol);

  ASSERT_TRUE(world.ray_cast_closest(Vec3(Real(0.5), 5, Real(-1.5)), Vec3(0, -1, 0), 10, {}, hit));
  EXPECT_TRUE(
      hit_matches(hit, Vec3(Real(0.5), Real(1.5), Real(-1.5)), Vec3(0, 1, 0), 3.5, kRayTol));

  // Passing above the top face (y = 1.5) misses.
  EXPECT_FALSE(world.ray_cast_closest(Vec3(-5, 2, 0), Vec3(1, 0, 0), 10, {}, hit));
}

TEST(RayCast, RotatedBox) {
  // Unit cube rotated 45° about y. Its face with local normal −x has world normal
  // (−√½, 0, √½) and equation (x − z)/√2 = −1. The ray z = 0.3, y = 0 along +x meets it at
  // x = 0.3 − √2, i.e. after 5.3 − √2 m from x = −5.
  World world = query_world();
  add_box(world, Vec3::Zero(), Vec3::Ones(),
          Quat(Eigen::AngleAxis<Real>(Real(EIGEN_PI / 4), Vec3::UnitY())));
  settle(world);
  RayHit hit;
  ASSERT_TRUE(world.ray_cast_closest(Vec3(-5, 0, Real(0.3)), Vec3(1, 0, 0), 10, {}, hit));
  const double s2 = std::sqrt(2.0);
  EXPECT_TRUE(hit_matches(hit, Vec3(Real(0.3 - s2), 0, Real(0.3)),
                          Vec3(Real(-1 / s2), 0, Real(1 / s2)), 5.3 - s2, kRayTol));
}

TEST(RayCast, MeshTriangleBothSides) {
  World world = query_world();
  const ShapeId mesh = add_mesh(world, {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 0, 2)}, {0, 1, 2});
  settle(world);
  RayHit hit;
  ASSERT_TRUE(world.ray_cast_closest(Vec3(Real(0.5), 3, Real(0.5)), Vec3(0, -1, 0), 10, {}, hit));
  EXPECT_TRUE(is_shape(hit.target, mesh));
  EXPECT_TRUE(hit_matches(hit, Vec3(Real(0.5), 0, Real(0.5)), Vec3(0, 1, 0), 3, kRayTol));
  // Two-sided: from below the normal points down, back at the caster.
  ASSERT_TRUE(world.ray_cast_closest(Vec3(Real(0.5), -3, Real(0.5)), Vec3(0, 1, 0), 10, {}, hit));
  EXPECT_TRUE(hit_matches(hit, Vec3(Real(0.5), 0, Real(0.5)), Vec3(0, -1, 0), 3, kRayTol));
  // Outside the triangle (x + z = 3 > 2): miss.
  EXPECT_FALSE(world.ray_cast_closest(Vec3(Real(1.5), 3, Real(1.5)), Vec3(0, -1, 0), 10, {}, hit));
}

TEST(RayCast, TiltedMeshTriangle) {
  // Triangle in the plane x + z = 1: (1,0,0), (0,0,1), (0.5,2,0.5). The ray from (0, 0.5, 0)
  // along (1,0,1)/√2 meets it at (0.5, 0.5, 0.5) after √0.5 m.
  World world = query_world();
  add_mesh(world, {Vec3(1, 0, 0), Vec3(0, 0, 1), Vec3(Real(0.5), 2, Real(0.5))}, {0, 1, 2});
  settle(world);
  RayHit hit;
  const Real h = Real(1 / std::sqrt(2.0));
  ASSERT_TRUE(world.ray_cast_closest(Vec3(0, Real(0.5), 0), Vec3(h, 0, h), 10, {}, hit));
  EXPECT_TRUE(hit_matches(hit, Vec3(Real(0.5), Real(0.5), Real(0.5)), Vec3(-h, 0, -h),
                          std::sqrt(0.5), kRayTol));
}

TEST(RayCast, SphereBody) {
  // Sphere r = 0.5 at the origin; the ray y = 0.3 along +x enters at x = −√(0.25 − 0.09) = −0.4.
  World world = query_world();
  const BodyId ball = add_sphere(world, Vec3::Zero());
  settle(world);
  RayHit hit;
  ASSERT_TRUE(world.ray_cast_closest(Vec3(-5, Real(0.3), 0), Vec3(1, 0, 0), 10, {}, hit));
  EXPECT_TRUE(is_body(hit.target, ball));
  EXPECT_TRUE(hit_matches(hit, Vec3(Real(-0.4), Real(0.3), 0), Vec3(Real(-0.8), Real(0.6), 0), 4.6,
                          kRayTol));
  EXPECT_NEAR(hit.fraction, 0.46, kRayTol);
  // Passing above it misses.
  EXPECT_FALSE(world.ray_cast_closest(Vec3(-5, Real(0.51), 0), Vec3(1, 0, 0), 10, {}, hit));
}

/// Floor y = 0, box top at 1.25, sphere body top at 2.5, sensor top at 4.5, all on the y axis.
struct Stack {
  World world;
  ShapeId floor, box;
  BodyId ball, sensor;
};

Stack make_stack() {
  Stack s{query_world(), {}, {}, {}, {}};
  s.floor = add_floor(s.world);
  BoxDef box;
  box.center = Vec3(0, 1, 0);
  box.half_extents = Vec3(Real(0.5), Real(0.25), Real(0.5));
  box.filter.layer = 4;
  s.box = unwrap(s.world.add_box(box), "add_box");
  BodyDef ball = sphere_def(Vec3(0, 2, 0));
  ball.filter.layer = 2;
  s.ball = add_body(s.world, ball);
  BodyDef sensor = sphere_def(Vec3(0, 4, 0));
  sensor.sensor = true;
  s.sensor = add_body(s.world, sensor);
  settle(s.world);
  return s;
}

const Vec3 kTop(0, 10, 0);
const Vec3 kDown(0, -1, 0);

TEST(RayCast, ClosestAndAllSortedByDistance) {
  Stack s = make_stack();
  RayHit hit;
  ASSERT_TRUE(s.world.ray_cast_closest(kTop, kDown, 20, {}, hit));
  EXPECT_TRUE(is_body(hit.target, s.ball)) << "sensors are skipped by default";
  EXPECT_TRUE(hit_matches(hit, Vec3(0, Real(2.5), 0), Vec3(0, 1, 0), 7.5, kRayTol));

  // One hit per object (the entry point), sorted: ball 7.5, box 8.75, floor 10.
  const std::vector<RayHit> all = s.world.ray_cast_all(kTop, kDown, 20, {});
  ASSERT_EQ(all.size(), 3u);
  EXPECT_TRUE(is_body(all[0].target, s.ball));
  EXPECT_TRUE(is_shape(all[1].target, s.box));
  EXPECT_TRUE(is_shape(all[2].target, s.floor));
  EXPECT_NEAR(all[0].distance, 7.5, kRayTol);
  EXPECT_NEAR(all[1].distance, 8.75, kRayTol);
  EXPECT_NEAR(all[2].distance, 10, kRayTol);
  EXPECT_TRUE(near(all[1].point, Vec3(0, Real(1.25), 0), kRayTol));
  EXPECT_NEAR(all[2].fraction, 0.5, kRayTol);

  // max_distance cuts the list: 9 m reaches the ball and the box only.
  EXPECT_EQ(s.world.ray_cast_all(kTop, kDown, 9, {}).size(), 2u);
}

TEST(RayCast, FiltersSelectTargets) {
  Stack s = make_stack();
  RayHit hit;

  QueryFilter no_layer2;
  no_layer2.mask = ~2u;  // the ball is on layer 2
  ASSERT_TRUE(s.world.ray_cast_closest(kTop, kDown, 20, no_layer2, hit));
  EXPECT_TRUE(is_shape(hit.target, s.box));

  QueryFilter no_layer4;
  no_layer4.mask = ~4u;  // the box is on layer 4 (statics are filtered by layer too)
  const std::vector<RayHit> all = s.world.ray_cast_all(kTop, kDown, 20, no_layer4);
  ASSERT_EQ(all.size(), 2u);
  EXPECT_TRUE(is_body(all[0].target, s.ball));
  EXPECT_TRUE(is_shape(all[1].target, s.floor));

  QueryFilter statics_only;
  statics_only.bodies = false;
  ASSERT_TRUE(s.world.ray_cast_closest(kTop, kDown, 20, statics_only, hit));
  EXPECT_TRUE(is_shape(hit.target, s.box));

  QueryFilter bodies_only;
  bodies_only.statics = false;
  EXPECT_EQ(s.world.ray_cast_all(kTop, kDown, 20, bodies_only).size(), 1u);

  QueryFilter ignore_ball;
  ignore_ball.ignore = s.ball;
  ASSERT_TRUE(s.world.ray_cast_closest(kTop, kDown, 20, ignore_ball, hit));
  EXPECT_TRUE(is_shape(hit.target, s.box));

  bodies_only.ignore = s.ball;
  EXPECT_FALSE(s.world.ray_cast_closest(kTop, kDown, 20, bodies_only, hit));

  QueryFilter with_sensors;
  with_sensors.sensors = true;
  ASSERT_TRUE(s.world.ray_cast_closest(kTop, kDown, 20, with_sensors, hit));
  EXPECT_TRUE(is_body(hit.target, s.sensor));
  EXPECT_NEAR(hit.distance, 5.5, kRayTol);
  EXPECT_EQ(s.world.ray_cast_all(kTop, kDown, 20, with_sensors).size(), 4u);

  QueryFilter nothing;
  nothing.mask = 0;
  EXPECT_FALSE(s.world.ray_cast_closest(kTop, kDown, 20, nothing, hit));
}

TEST(RayCast, QueriesSeeBodiesCreatedAndMovedBetweenSteps) {
  // Not stated outright by the header ("queries (between steps)"), but a game creates a body and
  // queries it before the next step: the query must see it where it is now.
  World world = query_world();
  add_floor(world);
  settle(world);
  const BodyId ball = add_sphere(world, Vec3(0, 2, 0));  // no step after creation
  RayHit hit;
  ASSERT_TRUE(world.ray_cast_closest(kTop, kDown, 20, {}, hit));
  EXPECT_TRUE(is_body(hit.target, ball));
  EXPECT_NEAR(hit.distance, 7.5, kRayTol);
  RICOCHET_ASSERT_OK(world.set_transform(ball, Vec3(5, 2, 0), Quat::Identity()));
  ASSERT_TRUE(world.ray_cast_closest(kTop, kDown, 20, {}, hit));
  EXPECT_FALSE(is_body(hit.target, ball)) << "the ball was moved away";
  RICOCHET_ASSERT_OK(world.destroy_body(ball));
  ASSERT_TRUE(world.ray_cast_closest(Vec3(5, 10, 0), kDown, 20, {}, hit));
  EXPECT_FALSE(is_body(hit.target, ball)) << "the ball was destroyed";
}

TEST(SphereCast, AgainstPlane) {
  World world = query_world();
  const ShapeId floor = add_floor(world);
  settle(world);
  RayHit hit;
  // Radius 0.25 from y = 5 downward: touches when the centre is at 0.25, after 4.75 m; the touch
  // point is on the plane under the centre.
  ASSERT_TRUE(world.sphere_cast(Vec3(0, 5, 0), Real(0.25), kDown, 10, {}, hit));
  EXPECT_TRUE(is_shape(hit.target, floor));
  EXPECT_TRUE(hit_matches(hit, Vec3(0, 0, 0), Vec3(0, 1, 0), 4.75, kRayTol));
  EXPECT_NEAR(hit.fraction, 0.475, kRayTol);
  // Moving parallel to the plane 0.25 m above the touching height never touches it.
  EXPECT_FALSE(world.sphere_cast(Vec3(0, Real(0.5), 0), Real(0.25), Vec3(1, 0, 0), 10, {}, hit));
}

TEST(SphereCast, AgainstSphereBody) {
  World world = query_world();
  add_floor(world);
  const BodyId ball = add_sphere(world, Vec3(3, Real(0.6), 0));
  settle(world);
  RayHit hit;
  // Cast radius 0.25 along y = 0.6: centres 0.75 apart at x = 2.25; touch point at x = 2.5.
  ASSERT_TRUE(world.sphere_cast(Vec3(0, Real(0.6), 0), Real(0.25), Vec3(1, 0, 0), 10, {}, hit));
  EXPECT_TRUE(is_body(hit.target, ball));
  EXPECT_TRUE(hit_matches(hit, Vec3(Real(2.5), Real(0.6), 0), Vec3(-1, 0, 0), 2.25, kRayTol));
  QueryFilter ignore;
  ignore.ignore = ball;
  EXPECT_FALSE(
      world.sphere_cast(Vec3(0, Real(0.6), 0), Real(0.25), Vec3(1, 0, 0), 10, ignore, hit));
}

TEST(SphereCast, AgainstBoxEdge) {
  // Unit cube at the origin. A sphere r = 0.5 along y = 1.2 passes 0.2 above the top face, so it
  // first touches the edge x = −1, y = 1: centre at x = −1 − √(0.25 − 0.04), i.e. after
  // 4 − √0.21 m; normal (centre − edge)/r = (−√0.21, 0.2, 0)/0.5.
  World world = query_world();
  add_box(world, Vec3::Zero(), Vec3::Ones());
  settle(world);
  RayHit hit;
  ASSERT_TRUE(world.sphere_cast(Vec3(-5, Real(1.2), 0), Real(0.5), Vec3(1, 0, 0), 10, {}, hit));
  const double s = std::sqrt(0.21);
  EXPECT_TRUE(
      hit_matches(hit, Vec3(-1, 1, 0), Vec3(Real(-s / 0.5), Real(0.4), 0), 4 - s, kCastTol));
}

TEST(SphereCast, AgainstMeshTriangleFace) {
  World world = query_world();
  add_mesh(world, {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 0, 2)}, {0, 1, 2});
  settle(world);
  RayHit hit;
  ASSERT_TRUE(world.sphere_cast(Vec3(Real(0.5), 3, Real(0.5)), Real(0.25), kDown, 10, {}, hit));
  EXPECT_TRUE(hit_matches(hit, Vec3(Real(0.5), 0, Real(0.5)), Vec3(0, 1, 0), 2.75, kCastTol));
}

bool contains_shape(const std::vector<ContactTarget>& v, ShapeId id) {
  return std::any_of(v.begin(), v.end(), [&](const ContactTarget& t) { return is_shape(t, id); });
}
bool contains_body(const std::vector<ContactTarget>& v, BodyId id) {
  return std::any_of(v.begin(), v.end(), [&](const ContactTarget& t) { return is_body(t, id); });
}

TEST(OverlapSphere, FindsExactlyTheOverlappingObjects) {
  World world = query_world();
  const ShapeId floor = add_floor(world);
  const ShapeId box = add_box(world, Vec3(-3, Real(0.5), 0), Vec3::Constant(Real(0.5)));
  const BodyId near_ball = add_sphere(world, Vec3(Real(0.8), Real(0.6), 0));
  const BodyId far_ball = add_sphere(world, Vec3(3, Real(0.6), 0));
  settle(world);

  // Centre (0, 0.3, 0), r = 0.5: dips 0.2 below the floor; 0.854 m from the near ball's centre
  // (< 1); 3 m from the far ball; 2.5 m from the box. Order is unspecified.
  const std::vector<ContactTarget> found =
      world.overlap_sphere(Vec3(0, Real(0.3), 0), Real(0.5), {});
  EXPECT_EQ(found.size(), 2u);
  EXPECT_TRUE(contains_shape(found, floor));
  EXPECT_TRUE(contains_body(found, near_ball));
  EXPECT_FALSE(contains_body(found, far_ball));
  EXPECT_FALSE(contains_shape(found, box));

  QueryFilter bodies_only;
  bodies_only.statics = false;
  const std::vector<ContactTarget> bodies =
      world.overlap_sphere(Vec3(0, Real(0.3), 0), Real(0.5), bodies_only);
  ASSERT_EQ(bodies.size(), 1u);
  EXPECT_TRUE(is_body(bodies[0], near_ball));

  // Centre (−2.2, 0.6, 0), r = 0.5: 0.3 m from the box's +x face, 0.1 m above the floor.
  const std::vector<ContactTarget> at_box =
      world.overlap_sphere(Vec3(Real(-2.2), Real(0.6), 0), Real(0.5), {});
  ASSERT_EQ(at_box.size(), 1u);
  EXPECT_TRUE(is_shape(at_box[0], box));

  EXPECT_TRUE(world.overlap_sphere(Vec3(0, 10, 0), Real(0.5), {}).empty());
}

}  // namespace
}  // namespace ricochet::physics::test::ray_cast_test
