// Degenerate configurations: spheres created overlapping or at exactly the same centre, contacts
// with zero relative velocity, spheres centred exactly on or resting exactly over a mesh edge or
// vertex, rays along a triangle edge or through a vertex, and spheres of radius 0.1 mm and 1 km.
// Each must give a finite, sensible result: unit normals pointing the right way, overlaps
// resolved, resting bodies left at rest, queries that hit cleanly or miss cleanly.

#include "test_util.h"

namespace ricochet::physics::test::extremes_degenerate_test {
namespace {

constexpr int kTwoSeconds = 120;  ///< steps at 60 Hz

/// |n| = 1 within float rounding, and finite.
::testing::AssertionResult is_unit(const Vec3& n) {
  if (!n.allFinite()) return ::testing::AssertionFailure() << "normal is not finite";
  const double error = std::abs(to_d(n).norm() - 1);
  if (error > 1e-5) {
    return ::testing::AssertionFailure()
           << "normal (" << n.transpose() << ") has length " << to_d(n).norm();
  }
  return ::testing::AssertionSuccess();
}

/// Every begin and impulse event of the last step has a unit normal; returns how many there were.
int expect_unit_event_normals(const World& world, const std::string& what) {
  int count = 0;
  for (const ContactBeginEvent& e : world.contact_begin_events()) {
    EXPECT_TRUE(is_unit(e.normal)) << what << ": begin event";
    EXPECT_TRUE(e.point.allFinite()) << what << ": begin event point";
    ++count;
  }
  for (const ContactImpulseEvent& e : world.contact_impulse_events()) {
    EXPECT_TRUE(is_unit(e.normal)) << what << ": impulse event";
    EXPECT_TRUE(std::isfinite(e.normal_impulse)) << what << ": impulse";
    ++count;
  }
  return count;
}

// ---------------------------------------------------------------------------------------------
// Overlapping and coincident spheres

/// Fastest a body may leave an overlap it was created in: position correction pushes at most at
/// max_correction_speed (Baumgarte leaves that velocity in the body, so in zero gravity it keeps
/// flying; SplitImpulse and SoftStep were measured to leave 0–1.9 m/s).
double push_limit(const World& world) {
  return double(world.definition().max_correction_speed) * (1 + 1e-4);
}

/// Zero gravity: spheres created at `centres` (radius 0.5, 1 kg) must be pushed apart to touching
/// (less the slop and 1 mm) within 2 s, every contact normal unit length, the centre of mass
/// unmoved (the pushes are equal and opposite) and nothing thrown faster than push_limit().
void expect_separate(const std::vector<Vec3>& centres, PositionCorrection correction,
                     const std::string& what) {
  World world = make_world(with_correction(space_def(), correction));
  std::vector<BodyId> ids;
  for (const Vec3& c : centres) ids.push_back(add_sphere(world, c));
  Eigen::Vector3d centre_of_mass = Eigen::Vector3d::Zero();
  for (const Vec3& c : centres) centre_of_mass += to_d(c) / double(centres.size());
  const double max_speed = push_limit(world);
  int events = 0;
  for (int i = 0; i < kTwoSeconds; ++i) {
    ASSERT_TRUE(run(world, 1)) << what;
    events += expect_unit_event_normals(world, what);
    for (BodyId id : ids) {
      ASSERT_TRUE(bounded(state_of(world, id), Vec3::Zero(), 2 * max_speed + 5, max_speed))
          << what << ", step " << i;
    }
  }
  EXPECT_GT(events, 0) << what << ": the overlap was never reported as a contact";
  const double touching = 1 - double(world.definition().linear_slop) - 1e-3;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  for (std::size_t a = 0; a < ids.size(); ++a) {
    const Eigen::Vector3d pa = to_d(state_of(world, ids[a]).position);
    com += pa / double(ids.size());
    for (std::size_t b = a + 1; b < ids.size(); ++b) {
      const double d = (to_d(state_of(world, ids[b]).position) - pa).norm();
      EXPECT_GE(d, touching) << what << ": spheres " << a << " and " << b << " still overlap";
    }
  }
  EXPECT_LT((com - centre_of_mass).norm(), 1e-4) << what << ": the centre of mass moved";
}

TEST(ExtremeDegenerate, OverlappingSpheresSeparate) {
  for (const PositionCorrection c : kAllCorrections) {
    expect_separate({Vec3::Zero(), Vec3(Real(0.5), 0, 0)}, c, cat(correction_name(c), " half"));
    expect_separate({Vec3::Zero(), Vec3(Real(1e-6), Real(2e-6), 0)}, c,
                    cat(correction_name(c), " nearly coincident"));
  }
}

TEST(ExtremeDegenerate, CoincidentSpheresSeparate) {
  for (const PositionCorrection c : kAllCorrections) {
    expect_separate({Vec3(1, 2, 3), Vec3(1, 2, 3)}, c, cat(correction_name(c), " two"));
    expect_separate({Vec3::Zero(), Vec3::Zero(), Vec3::Zero()}, c,
                    cat(correction_name(c), " three"));
  }
}

TEST(ExtremeDegenerate, CoincidentSpheresOnTheFloorEndStacked) {
  // Gravity on, both created resting on the floor at the same point: they must end one on top of
  // the other (or side by side), both on or above the floor, at rest.
  World world = make_world();
  add_floor(world);
  const BodyId a = add_sphere(world, Vec3(0, Real(0.5), 0));
  const BodyId b = add_sphere(world, Vec3(0, Real(0.5), 0));
  // The correction's push plus one step of gravity.
  const double max_speed = push_limit(world) + double(kGravity * kDt60);
  for (int i = 0; i < 3 * kTwoSeconds; ++i) {
    ASSERT_TRUE(run(world, 1));
    expect_unit_event_normals(world, "coincident on floor");
    ASSERT_TRUE(bounded(state_of(world, a), Vec3::Zero(), 5, max_speed)) << "step " << i;
    ASSERT_TRUE(bounded(state_of(world, b), Vec3::Zero(), 5, max_speed)) << "step " << i;
  }
  const BodyState sa = state_of(world, a), sb = state_of(world, b);
  const double slop = double(world.definition().linear_slop) + 1e-3;
  EXPECT_GE(to_d(sb.position - sa.position).norm(), 1 - slop);
  EXPECT_GE(double(std::min(sa.position.y(), sb.position.y())), 0.5 - slop);
  EXPECT_LT(double(sa.linear_velocity.norm() + sb.linear_velocity.norm()), 0.1);
}

// ---------------------------------------------------------------------------------------------
// Zero relative velocity

TEST(ExtremeDegenerate, ExactlyTouchingAtRestStaysPut) {
  // No gravity, no velocity, every gap exactly zero: no contact may push (nothing to correct),
  // so nothing moves at all.
  World world = make_world(space_def());
  add_floor(world);
  add_box(world, Vec3(10, 1, 0), Vec3(1, 1, 1));
  add_mesh(world, {Vec3(-12, 0, -1), Vec3(-12, 2, -1), Vec3(-12, 2, 1)}, {0, 1, 2});
  const std::vector<Vec3> starts = {Vec3(0, Real(0.5), 0), Vec3(1, Real(0.5), 0),
                                    Vec3(Real(8.5), 1, Real(0.25)),
                                    Vec3(Real(-11.5), Real(1.5), Real(-0.25))};
  std::vector<BodyId> ids;
  for (const Vec3& p : starts) ids.push_back(add_sphere(world, p));
  ASSERT_TRUE(run(world, kTwoSeconds));
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const BodyState s = state_of(world, ids[k]);
    EXPECT_TRUE(near(s.position, starts[k], 1e-6)) << "sphere " << k;
    EXPECT_LT(s.linear_velocity.norm(), 1e-6) << "sphere " << k;
    EXPECT_LT(s.angular_velocity.norm(), 1e-6) << "sphere " << k;
  }
}

TEST(ExtremeDegenerate, ExactlyTouchingUnderGravityStaysPut) {
  // Gravity on: a sphere exactly on the floor and one exactly on top of it. The solver must hold
  // them where they are, within the slop, and at rest.
  World world = make_world();
  add_floor(world);
  const BodyId low = add_sphere(world, Vec3(0, Real(0.5), 0));
  const BodyId high = add_sphere(world, Vec3(0, Real(1.5), 0));
  for (int i = 0; i < kTwoSeconds; ++i) {
    ASSERT_TRUE(run(world, 1));
    expect_unit_event_normals(world, "stack");
  }
  const double slop = double(world.definition().linear_slop) + 1e-3;
  EXPECT_TRUE(near(state_of(world, low).position, Vec3(0, Real(0.5), 0), slop));
  EXPECT_TRUE(near(state_of(world, high).position, Vec3(0, Real(1.5), 0), 2 * slop));
  EXPECT_LT(state_of(world, high).linear_velocity.norm(), 1e-2);
}

// ---------------------------------------------------------------------------------------------
// Mesh edges and vertices

/// A 2 m × 2 m square in the plane y = 0 made of 2×2 quads, each split along a diagonal, wound
/// so the face normals point up: the centre vertex (0, 0, 0) is shared by six triangles.
ShapeId add_grid(World& world) {
  std::vector<Vec3> vertices;
  for (int i = 0; i <= 2; ++i) {
    for (int j = 0; j <= 2; ++j) vertices.emplace_back(Real(i - 1), 0, Real(j - 1));
  }
  std::vector<std::uint32_t> indices;
  for (std::uint32_t i = 0; i < 2; ++i) {
    for (std::uint32_t j = 0; j < 2; ++j) {
      const std::uint32_t a = i * 3 + j, b = a + 3, c = a + 4, d = a + 1;
      indices.insert(indices.end(), {a, d, c, a, c, b});
    }
  }
  return add_mesh(world, vertices, indices);
}

struct MeshFeature {
  const char* name;
  Vec3 point;  ///< on the mesh, in the plane y = 0
};

const MeshFeature kFeatures[] = {
    {"shared vertex", Vec3(0, 0, 0)},
    {"shared straight edge", Vec3(0, 0, Real(0.5))},
    {"shared diagonal edge", Vec3(Real(0.5), 0, Real(0.5))},
    {"boundary edge", Vec3(1, 0, Real(-0.3))},
    {"boundary corner", Vec3(1, 0, 1)},
};

TEST(ExtremeDegenerate, SphereCentredExactlyOnMeshEdgeOrVertexIsPushedOut) {
  // Zero gravity; the sphere's centre lies on the feature itself (distance 0, direction
  // undefined). It must leave along the face normal, to either side (the mesh is two-sided),
  // reported normals unit length, pointing from the sphere into the mesh.
  for (const MeshFeature& f : kFeatures) {
    for (const PositionCorrection c : kAllCorrections) {
      const std::string what = cat(f.name, ", ", correction_name(c));
      World world = make_world(with_correction(space_def(), c));
      add_grid(world);
      const BodyId id = add_sphere(world, f.point, Real(0.5));
      const double max_speed = push_limit(world);
      std::vector<Vec3> normals;
      for (int i = 0; i < kTwoSeconds; ++i) {
        ASSERT_TRUE(run(world, 1)) << what;
        expect_unit_event_normals(world, what);
        for (const ContactBeginEvent& e : world.contact_begin_events()) normals.push_back(e.normal);
        for (const ContactImpulseEvent& e : world.contact_impulse_events()) {
          normals.push_back(e.normal);
        }
        ASSERT_TRUE(bounded(state_of(world, id), f.point, 2 * max_speed + 5, max_speed))
            << what << ", step " << i;
      }
      const BodyState s = state_of(world, id);
      const double height = double(s.position.y());
      const double slop = double(world.definition().linear_slop) + 1e-3;
      EXPECT_GE(std::abs(height), 0.5 - slop) << what << ": still inside the mesh";
      EXPECT_FALSE(normals.empty()) << what << ": the overlap was never reported as a contact";
      for (const Vec3& n : normals) {
        // From the sphere into the mesh: opposite to the side the sphere left to, and vertical.
        EXPECT_LT(double(n.y()) * (height > 0 ? 1 : -1), -0.9999)
            << what << ": normal (" << n.transpose() << "), sphere ended at y = " << height;
      }
      EXPECT_LT(
          std::hypot(double(s.position.x() - f.point.x()), double(s.position.z() - f.point.z())),
          1e-3)
          << what << ": pushed sideways instead of along the face normal";
    }
  }
}

TEST(ExtremeDegenerate, SphereRestingExactlyOverMeshEdgeOrVertexIsHeldStraightUp) {
  // Gravity on; the sphere touches the mesh exactly at the feature. The contact normal must be
  // unit length and vertical (pointing from the sphere down into the mesh), the sphere must stay
  // where it is: no sideways kick off a ghost edge, no sinking.
  for (const MeshFeature& f : kFeatures) {
    const std::string what = f.name;
    World world = make_world();
    add_grid(world);
    const Vec3 start = f.point + Vec3(0, Real(0.5), 0);
    const BodyId id = add_sphere(world, start, Real(0.5));
    int normals = 0;
    for (int i = 0; i < kTwoSeconds; ++i) {
      ASSERT_TRUE(run(world, 1)) << what;
      expect_unit_event_normals(world, what);
      for (const ContactImpulseEvent& e : world.contact_impulse_events()) {
        EXPECT_LT(double(e.normal.y()), -0.9999)
            << what << ": normal (" << e.normal.transpose() << ") at step " << i;
        ++normals;
      }
    }
    EXPECT_GT(normals, 0) << what << ": no contact carried the sphere";
    const BodyState s = state_of(world, id);
    EXPECT_TRUE(near(s.position, start, double(world.definition().linear_slop) + 1e-3)) << what;
    EXPECT_LT(s.linear_velocity.norm(), 1e-2) << what;
  }
}

// ---------------------------------------------------------------------------------------------
// Rays along edges and through vertices

/// A hit of a cast of `radius` (0 for a ray) must be finite and consistent: unit normal facing
/// the caster, fraction in [0, 1], distance = fraction · max_distance, and the point where the
/// cast's surface touches: origin + distance · direction − radius · normal.
::testing::AssertionResult consistent(const RayHit& hit, const Vec3& origin, const Vec3& dir,
                                      Real max_distance, Real radius = 0) {
  if (!hit.point.allFinite() || !std::isfinite(hit.fraction) || !std::isfinite(hit.distance)) {
    return ::testing::AssertionFailure() << "non-finite hit";
  }
  if (::testing::AssertionResult unit = is_unit(hit.normal); !unit) return unit;
  if (hit.fraction < 0 || hit.fraction > 1) {
    return ::testing::AssertionFailure() << "fraction " << hit.fraction;
  }
  if (std::abs(double(hit.distance) - double(hit.fraction) * double(max_distance)) > 1e-4) {
    return ::testing::AssertionFailure()
           << "distance " << hit.distance << " vs fraction " << hit.fraction;
  }
  const Vec3 touch = origin + dir.normalized() * hit.distance - hit.normal * radius;
  if (!near(hit.point, touch, 1e-4)) {
    return ::testing::AssertionFailure()
           << "point (" << hit.point.transpose() << ") is not where the cast touches";
  }
  if (double(hit.normal.dot(dir.normalized())) > 1e-6) {
    return ::testing::AssertionFailure()
           << "normal (" << hit.normal.transpose() << ") faces away from the caster";
  }
  return ::testing::AssertionSuccess();
}

TEST(ExtremeDegenerate, RaysThroughMeshVerticesAndEdgesHitExactly) {
  // Straight down (and up) through the shared vertex, a shared edge, a boundary edge and the
  // boundary corner: each belongs to the mesh, so the ray hits it at distance 1 with the face
  // normal facing the caster.
  World world = make_world(space_def());
  add_grid(world);
  ASSERT_TRUE(run(world, 1));  // see RayBeforeTheFirstStepSeesTheMesh
  for (const MeshFeature& f : kFeatures) {
    for (const Real side : {Real(1), Real(-1)}) {
      const Vec3 origin = f.point + Vec3(0, side, 0), dir(0, -side, 0);
      RayHit hit;
      ASSERT_TRUE(world.ray_cast_closest(origin, dir, 3, {}, hit)) << f.name << " side " << side;
      EXPECT_TRUE(consistent(hit, origin, dir, 3)) << f.name;
      EXPECT_NEAR(double(hit.distance), 1, 1e-5) << f.name;
      EXPECT_TRUE(near(hit.normal, Vec3(0, side, 0), 1e-5)) << f.name;
      for (const RayHit& h : world.ray_cast_all(origin, dir, 3, {})) {
        EXPECT_TRUE(consistent(h, origin, dir, 3)) << f.name << " (ray_cast_all)";
      }
    }
  }
}

TEST(ExtremeDegenerate, RaysAlongMeshEdgesHitCleanlyOrMissCleanly) {
  // In the mesh's plane, along an edge line (through vertices, grazing every triangle on it):
  // a hit or a miss are both acceptable, but a hit must be finite and consistent.
  World world = make_world(space_def());
  add_grid(world);
  ASSERT_TRUE(run(world, 1));  // see RayBeforeTheFirstStepSeesTheMesh
  struct Ray {
    const char* name;
    Vec3 origin, dir;
  };
  const Ray rays[] = {
      {"along the shared edge x = 0", Vec3(0, 0, -3), Vec3(0, 0, 1)},
      {"along the boundary edge x = 1", Vec3(1, 0, -3), Vec3(0, 0, 1)},
      {"along the diagonal", Vec3(-3, 0, -3), Vec3(1, 0, 1)},
      {"starting on a vertex, along an edge", Vec3(0, 0, 0), Vec3(1, 0, 0)},
      {"grazing a corner", Vec3(3, 0, -1), Vec3(-1, 0, 1)},
      {"oblique through a vertex", Vec3(2, 1, 2), Vec3(-1, -1, -1)},
  };
  for (const Ray& r : rays) {
    RayHit hit;
    if (world.ray_cast_closest(r.origin, r.dir, 10, {}, hit)) {
      EXPECT_TRUE(consistent(hit, r.origin, r.dir, 10)) << r.name;
    }
    for (const RayHit& h : world.ray_cast_all(r.origin, r.dir, 10, {})) {
      EXPECT_TRUE(consistent(h, r.origin, r.dir, 10)) << r.name << " (ray_cast_all)";
    }
    if (world.sphere_cast(r.origin + Vec3(0, 1, 0), Real(0.25), r.dir, 10, {}, hit)) {
      EXPECT_TRUE(consistent(hit, r.origin + Vec3(0, 1, 0), r.dir, 10, Real(0.25)))
          << r.name << " (sphere)";
    }
  }
}

TEST(ExtremeDegenerate, ObliqueRaysThroughMeshVerticesHitTheVertex) {
  // An oblique ray crossing the mesh's plane exactly at a vertex meets the mesh there and
  // nowhere else, so a hit must be at the vertex. Through the shared centre vertex (inside the
  // mesh) it must hit; through the boundary corner rounding may decide either way. 0.1 mm allows
  // float rounding at this scale (~1 µm) a hundred times over.
  World world = make_world(space_def());
  add_grid(world);
  ASSERT_TRUE(run(world, 1));  // see RayBeforeTheFirstStepSeesTheMesh
  for (const bool inside : {true, false}) {
    const Vec3 vertex = inside ? Vec3(0, 0, 0) : Vec3(1, 0, 1);
    for (const Vec3& dir : {Vec3(-1, -1, -1), Vec3(1, -1, Real(0.5)), Vec3(0, 1, -1)}) {
      const std::string what =
          cat("vertex (", vertex.transpose(), "), direction (", dir.transpose(), ")");
      const Vec3 origin = vertex - dir.normalized() * 2;
      RayHit hit;
      if (!world.ray_cast_closest(origin, dir, 10, {}, hit)) {
        EXPECT_FALSE(inside) << what << ": missed";
        continue;
      }
      EXPECT_TRUE(consistent(hit, origin, dir, 10)) << what;
      EXPECT_TRUE(near(hit.point, vertex, 1e-4)) << what;
    }
  }
}

TEST(ExtremeDegenerate, RayBeforeTheFirstStepSeesTheMesh) {
  // A world never stepped: queries run "between steps" too, so they must see static shapes added
  // since the last step. (Found here: the static BVH is rebuilt only inside step(), so this ray
  // misses; the tests above step once first.)
  World world = make_world(space_def());
  add_grid(world);
  add_box(world, Vec3(5, 0, 0), Vec3(1, 1, 1));
  RayHit hit;
  EXPECT_TRUE(world.ray_cast_closest(Vec3(Real(0.3), 1, Real(0.2)), Vec3(0, -1, 0), 3, {}, hit))
      << "mesh";
  EXPECT_TRUE(world.ray_cast_closest(Vec3(5, 3, 0), Vec3(0, -1, 0), 3, {}, hit)) << "box";
  EXPECT_FALSE(world.overlap_sphere(Vec3(5, 0, 0), Real(0.1), {}).empty()) << "box overlap";
}

// ---------------------------------------------------------------------------------------------
// Tiny and huge spheres

TEST(ExtremeDegenerate, TinySphereLandsAndRestsOnFloorBoxAndMesh) {
  // Radius 0.1 mm, 1 g, dropped 10 cm (1.4 m/s at impact, 150 radii per step): it must stop on
  // each surface, within the slop, not fall through.
  World world = make_world();
  add_floor(world);
  add_box(world, Vec3(1, Real(-0.5), 0), Vec3(Real(0.2), Real(0.7), Real(0.2)));
  add_mesh(world,
           {Vec3(-1.5, Real(0.3), -0.5), Vec3(-1.5, Real(0.3), 0.5), Vec3(-0.5, Real(0.3), 0)},
           {0, 1, 2});
  const Real r = Real(1e-4);
  const struct {
    const char* name;
    Vec3 start;
    Real surface;  ///< y of the surface below
  } drops[] = {{"floor", Vec3(0, Real(0.1), 0), 0},
               {"box", Vec3(1, Real(0.3), 0), Real(0.2)},
               {"mesh", Vec3(-1, Real(0.4), 0), Real(0.3)}};
  std::vector<BodyId> ids;
  for (const auto& d : drops) ids.push_back(add_sphere(world, d.start, r, Real(1e-3)));
  for (int i = 0; i < kTwoSeconds; ++i) {
    ASSERT_TRUE(run(world, 1));
    expect_unit_event_normals(world, "tiny");
  }
  const double slop = double(world.definition().linear_slop) + 1e-3;
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const BodyState s = state_of(world, ids[k]);
    ASSERT_TRUE(bounded(s, drops[k].start, 1, 2)) << drops[k].name;
    EXPECT_NEAR(double(s.position.y()), double(drops[k].surface + r), slop) << drops[k].name;
    EXPECT_LT(s.linear_velocity.norm(), 1e-2) << drops[k].name;
  }
}

TEST(ExtremeDegenerate, HugeSphereRestsAndCarriesSmallOnes) {
  // Radius 1 km, 1e9 kg, resting on the floor; a 0.5 m sphere resting on its top and a 0.1 mm
  // one dropped onto it. Centres near 2 km: float spacing there is 0.24 mm.
  World world = make_world();
  add_floor(world);
  const Real big = 1000;
  const BodyId huge = add_sphere(world, Vec3(0, big, 0), big, Real(1e9));
  const Vec3 small_start(0, 2 * big + Real(0.5), 0);
  const BodyId small = add_sphere(world, small_start, Real(0.5), 1);
  const BodyId tiny =
      add_sphere(world, Vec3(Real(0.01), 2 * big + Real(0.1), 3), Real(1e-4), Real(1e-3));
  for (int i = 0; i < kTwoSeconds; ++i) {
    ASSERT_TRUE(run(world, 1));
    expect_unit_event_normals(world, "huge");
  }
  const double slop = double(world.definition().linear_slop) + 1e-3;
  const BodyState h = state_of(world, huge), s = state_of(world, small), t = state_of(world, tiny);
  ASSERT_TRUE(bounded(h, Vec3(0, big, 0), slop, 0.01));
  ASSERT_TRUE(bounded(s, small_start, 2 * slop, 0.01));
  ASSERT_TRUE(is_finite(t));
  // The tiny one rests on the big sphere's surface (radius 1000 m + 0.1 mm from its centre).
  EXPECT_NEAR(to_d(t.position - h.position).norm(), double(big) + 1e-4, 2 * slop);
  EXPECT_LT(t.linear_velocity.norm(), 0.05);
}

}  // namespace
}  // namespace ricochet::physics::test::extremes_degenerate_test
