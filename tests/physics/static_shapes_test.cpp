// Spheres against static boxes and triangle meshes: resting stays put (same 1 mm / 1 mm/s bounds
// as on a plane: see resting_contact_test.cpp), and contacts exactly on a mesh edge or vertex,
// where several triangles report the same contact, give one sensible upward response.

#include "test_util.h"

namespace ricochet::physics::test::static_shapes_test {
namespace {

struct RestResult {
  double drift = 0, speed = 0, spin = 0;
  bool finite = true;
};

RestResult rest_for(World& world, BodyId id, int steps) {
  const Vec3 start = state_of(world, id).position;
  RestResult r;
  for (int i = 0; i < steps; ++i) {
    run_or_throw(world, 1);
    const BodyState s = state_of(world, id);
    r.finite = r.finite && is_finite(s);
    r.drift = std::max(r.drift, double((s.position - start).norm()));
    r.speed = std::max(r.speed, double(s.linear_velocity.norm()));
    r.spin = std::max(r.spin, double(s.angular_velocity.norm()));
  }
  return r;
}

void expect_rested(const RestResult& r, const std::string& what) {
  EXPECT_TRUE(r.finite) << what;
  EXPECT_LT(r.drift, 1e-3) << what;
  EXPECT_LT(r.speed, 1e-3) << what;
  EXPECT_LT(r.spin, 2e-3) << what;
}

/// Square [−2, 2]² at y = 0 as two triangles sharing the diagonal x = z.
ShapeId add_two_triangle_floor(World& world, const Material& m = {}) {
  return add_mesh(world, {Vec3(-2, 0, -2), Vec3(2, 0, -2), Vec3(2, 0, 2), Vec3(-2, 0, 2)},
                  {0, 1, 2, 0, 2, 3}, m);
}

/// 3×3 vertices over [−1, 1]² at y = 0, eight triangles; the centre vertex (0, 0, 0) is shared
/// by six of them.
ShapeId add_grid_floor(World& world, const Material& m = {}) {
  std::vector<Vec3> v;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) v.emplace_back(Real(i - 1), 0, Real(j - 1));
  std::vector<std::uint32_t> idx;
  for (std::uint32_t i = 0; i < 2; ++i) {
    for (std::uint32_t j = 0; j < 2; ++j) {
      const std::uint32_t a = i * 3 + j, b = (i + 1) * 3 + j, c = (i + 1) * 3 + j + 1,
                          d = i * 3 + j + 1;
      idx.insert(idx.end(), {a, b, c, a, c, d});
    }
  }
  return add_mesh(world, std::move(v), std::move(idx), m);
}

TEST(StaticShapes, SphereRestsOnBoxTop) {
  World world = make_world();  // sleeping off
  add_box(world, Vec3(0, Real(-0.5), 0), Vec3(2, Real(0.5), 2));
  const BodyId ball = add_sphere(world, Vec3(Real(0.3), Real(0.5), Real(-0.2)));
  expect_rested(rest_for(world, ball, 600), "box top");
}

TEST(StaticShapes, SphereRestsOnRotatedBoxTop) {
  // Rotated 30° about the vertical: the top face is still y = 0.
  World world = make_world();
  add_box(world, Vec3(0, Real(-0.5), 0), Vec3(2, Real(0.5), 1),
          Quat(Eigen::AngleAxis<Real>(Real(EIGEN_PI / 6), Vec3::UnitY())));
  const BodyId ball = add_sphere(world, Vec3(Real(0.2), Real(0.5), Real(0.1)));
  expect_rested(rest_for(world, ball, 600), "rotated box top");
}

TEST(StaticShapes, SphereRestsOnMeshFloorInsideATriangle) {
  World world = make_world();
  add_two_triangle_floor(world);
  const BodyId ball = add_sphere(world, Vec3(Real(0.5), Real(0.5), Real(-1)));
  expect_rested(rest_for(world, ball, 600), "mesh triangle interior");
}

TEST(StaticShapes, SphereRestsExactlyOnSharedMeshEdge) {
  World world = make_world();
  add_two_triangle_floor(world);
  const BodyId ball = add_sphere(world, Vec3(Real(0.7), Real(0.5), Real(0.7)));
  expect_rested(rest_for(world, ball, 600), "mesh diagonal edge");
}

TEST(StaticShapes, SphereRestsExactlyOnSharedMeshVertex) {
  World world = make_world();
  add_grid_floor(world);
  const BodyId ball = add_sphere(world, Vec3(0, Real(0.5), 0));
  expect_rested(rest_for(world, ball, 600), "mesh vertex shared by six triangles");
}

struct DropCase {
  const char* name;
  bool grid;   ///< grid floor (vertex case) instead of two triangles
  Vec3 where;  ///< x, z of the drop; y is set from the height
};

void PrintTo(const DropCase& c, std::ostream* os) {
  *os << c.name;
}

class MeshFeatureDropTest : public ::testing::TestWithParam<DropCase> {};

TEST_P(MeshFeatureDropTest, BounceIsUpwardAndSingle) {
  // Dropped from 1 m with e = 0.5 onto a flat mesh at, or a few cm from, a point where two or six
  // triangles meet. The surface is flat, so the true contact normal is +y: the bounce must be
  // straight up at e·√(2gh) (within 2·g·dt + 1%, as in bounce_test), not doubled by duplicate
  // contacts, and without sideways motion from a contact normal taken at an internal edge.
  const DropCase& c = GetParam();
  World world = make_world();
  const Material m = material(Real(0.5), Real(0.5));
  if (c.grid) {
    add_grid_floor(world, m);
  } else {
    add_two_triangle_floor(world, m);
  }
  const Real h = 1, r = Real(0.5);
  const BodyId ball = add_sphere(world, Vec3(c.where.x(), h + r, c.where.z()), r, 1, m);
  double rebound = 0;
  double max_sideways = 0;
  for (int i = 0; i < 120; ++i) {
    ASSERT_TRUE(run(world, 1));
    const BodyState s = state_of(world, ball);
    ASSERT_TRUE(is_finite(s)) << "step " << i;
    max_sideways = std::max({max_sideways, std::abs(double(s.linear_velocity.x())),
                             std::abs(double(s.linear_velocity.z()))});
    if (rebound == 0 && s.linear_velocity.y() > 0) rebound = s.linear_velocity.y();
  }
  const double v_i = std::sqrt(2 * double(kGravity) * double(h));
  EXPECT_NEAR(rebound, 0.5 * v_i, 2 * double(kGravity) * double(kDt60) + 0.01 * v_i) << c.name;
  EXPECT_LT(max_sideways, 1e-3) << c.name;
  const BodyState s = state_of(world, ball);
  EXPECT_NEAR(s.position.x(), c.where.x(), 1e-3) << c.name;
  EXPECT_NEAR(s.position.z(), c.where.z(), 1e-3) << c.name;
  EXPECT_GT(s.position.y(), 0) << c.name << ": fell through the mesh";
}

INSTANTIATE_TEST_SUITE_P(
    Features, MeshFeatureDropTest,
    ::testing::Values(DropCase{"Edge", false, Vec3(Real(0.7), 0, Real(0.7))},
                      DropCase{"Vertex", true, Vec3(0, 0, 0)},
                      DropCase{"Face", false, Vec3(Real(0.5), 0, Real(-1))},
                      // 3.5 cm from the shared edge: the neighbouring triangle's closest point is
                      // on that edge, off to the side, but the face below is the real contact.
                      DropCase{"NearEdge", false, Vec3(Real(0.7), 0, Real(0.75))},
                      DropCase{"NearVertex", true, Vec3(Real(0.03), 0, Real(-0.02))}),
    [](const ::testing::TestParamInfo<DropCase>& info) { return std::string(info.param.name); });

TEST(StaticShapes, SphereSettlesFromDropOntoVertex) {
  // e = 0 onto the shared vertex: after 2 s it rests on the vertex, still centred.
  World world = make_world();
  add_grid_floor(world);
  const BodyId ball = add_sphere(world, Vec3(0, Real(1.5), 0));
  ASSERT_TRUE(run(world, 120));
  const BodyState s = state_of(world, ball);
  ASSERT_TRUE(is_finite(s));
  EXPECT_TRUE(near(s.position, Vec3(0, Real(0.5), 0), 1e-3));
  EXPECT_LT(s.linear_velocity.norm(), 1e-3);
}

TEST(StaticShapes, SphereOnMeshBoundaryVertexIsPushedStraightUp) {
  // Centred exactly over a corner vertex of the mesh, 0.1 m below the touching height: the only
  // closest feature is the vertex, straight below, so the push-out is straight up.
  World world = make_world();
  add_two_triangle_floor(world);
  const BodyId ball = add_sphere(world, Vec3(2, Real(0.4), 2));
  ASSERT_TRUE(run(world, 60));
  const BodyState s = state_of(world, ball);
  ASSERT_TRUE(is_finite(s));
  // Pushed out to rest on the vertex, up to linear_slop of penetration being left uncorrected.
  const double slop = double(world.definition().linear_slop);
  EXPECT_GT(s.position.y(), 0.5 - slop - 1e-3) << "not pushed out of the vertex";
  EXPECT_LT(s.position.y(), 0.5 + 1e-3) << "pushed out too far";
  EXPECT_NEAR(s.position.x(), 2, 1e-4) << "sideways push from a vertex straight below";
  EXPECT_NEAR(s.position.z(), 2, 1e-4);
}

TEST(StaticShapes, SphereStopsOnBoxSideWall) {
  // Thrown horizontally at the side of a box (friction 0, e = 0): stops against the face x = −1.
  World world = make_world(space_def());
  add_box(world, Vec3::Zero(), Vec3::Ones(), Quat::Identity(), material(0, 0));
  BodyDef def = sphere_def(Vec3(-4, Real(0.3), Real(0.2)), Real(0.5), 1, material(0, 0));
  def.linear_velocity = Vec3(5, 0, 0);
  const BodyId ball = add_body(world, def);
  ASSERT_TRUE(run(world, 60));
  const BodyState s = state_of(world, ball);
  EXPECT_NEAR(s.position.x(), -1.5, 0.01) << "centre one radius from the face";
  EXPECT_NEAR(s.linear_velocity.x(), 0, 0.01);
  EXPECT_NEAR(s.position.y(), 0.3, 1e-3);
  EXPECT_NEAR(s.position.z(), 0.2, 1e-3);
}

TEST(StaticShapes, SphereRollsOffBoxEdgeAndFalls) {
  // Rolling across the top of a box it reaches the edge and drops to the floor: the box is finite.
  World world = make_world();
  add_floor(world);
  add_box(world, Vec3(0, Real(0.5), 0), Vec3(1, Real(0.5), 1));
  BodyDef def = sphere_def(Vec3(0, Real(1.25), 0), Real(0.25));
  def.linear_velocity = Vec3(2, 0, 0);
  def.angular_velocity = Vec3(0, 0, -8);
  const BodyId ball = add_body(world, def);
  ASSERT_TRUE(run(world, 120));
  const BodyState s = state_of(world, ball);
  EXPECT_NEAR(s.position.y(), 0.25, 2e-3) << "on the floor";
  EXPECT_GT(s.position.x(), 1.25);
}

}  // namespace
}  // namespace ricochet::physics::test::static_shapes_test
