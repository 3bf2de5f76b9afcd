// Queries against bodies give the answer of a scan of every body, computed here in closed form in
// double: on random scenes, after steps, and after set_transform / create / destroy between
// steps. Also: user_data in every hit, and lag compensation against caller-supplied spheres.
//
// Cases within 1e-3 m of a decision (grazing rays, a cast ending at a surface, an origin on a
// surface) are left out of the comparison: either answer is right there.

#include <algorithm>

#include "test_util.h"

namespace ricochet::physics::test::query_test {
namespace {

constexpr double kAmbiguous = 1e-3;  ///< m

struct Sphere {
  BodyId id;
  Eigen::Vector3d center;
  double radius;
};

std::vector<Sphere> all_spheres(const World& world) {
  std::vector<BodyId> ids(world.body_count());
  ids.resize(world.live_bodies(ids));
  std::vector<Vec3> positions(ids.size());
  if (!world.read_bodies(ids, {.positions = positions}).ok()) throw std::runtime_error("read");
  std::vector<Sphere> spheres;
  for (std::size_t i = 0; i < ids.size(); ++i)
    spheres.push_back({ids[i], to_d(positions[i]), double(state_of(world, ids[i]).radius)});
  return spheres;
}

enum class Verdict { Hit, Miss, Ambiguous };

/// The sphere of radius cast_radius moved from o along unit u for length, against sphere s: the
/// distance of first touch, in the world's rule (a cast starting inside reports nothing).
Verdict analytic_cast(const Eigen::Vector3d& o, const Eigen::Vector3d& u, double length,
                      double cast_radius, const Sphere& s, double& distance) {
  const double reach = s.radius + cast_radius;
  const Eigen::Vector3d m = o - s.center;
  const double b = m.dot(u), c = m.squaredNorm() - reach * reach;
  if (std::abs(m.norm() - reach) < kAmbiguous) return Verdict::Ambiguous;
  if (c < 0) return Verdict::Miss;
  const double closest = (m - u * b).norm();
  if (std::abs(closest - reach) < kAmbiguous) return Verdict::Ambiguous;
  if (closest > reach || b > 0) return Verdict::Miss;
  distance = -b - std::sqrt(b * b - c);
  if (std::abs(distance - length) < kAmbiguous) return Verdict::Ambiguous;
  return distance < length ? Verdict::Hit : Verdict::Miss;
}

Verdict analytic_overlap(const Eigen::Vector3d& center, double radius, const Sphere& s) {
  const double gap = (s.center - center).norm() - (radius + s.radius);
  if (std::abs(gap) < kAmbiguous) return Verdict::Ambiguous;
  return gap < 0 ? Verdict::Hit : Verdict::Miss;
}

QueryFilter bodies_only() {
  QueryFilter filter;
  filter.statics = false;
  return filter;
}

/// Compares ray_cast_all, sphere_cast and overlap_sphere with the closed-form scan; returns the
/// number of ray and overlap hits compared (so a test can check it compared something).
int compare_with_scan(const World& world, Lcg& rng, double half_width, int queries) {
  const std::vector<Sphere> spheres = all_spheres(world);
  int hits_seen = 0;
  for (int q = 0; q < queries; ++q) {
    const Vec3 o(rng.uniform(-half_width, half_width), rng.uniform(-half_width, half_width),
                 rng.uniform(-half_width, half_width));
    Vec3 dir(rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1));
    if (q % 5 == 0) dir = Vec3(rng.uniform(-1, 1), 0, rng.uniform(-1, 1));  // along cell planes
    if (q % 2 == 1 && !spheres.empty()) {  // at a body, give or take its radius
      const Sphere& s = spheres[static_cast<std::size_t>(rng.next() * double(spheres.size()))];
      dir = (s.center + Eigen::Vector3d::Constant(s.radius * (rng.next() - 0.5))).cast<Real>() - o;
    }
    if (dir.norm() < Real(0.1)) continue;
    const Real length = rng.uniform(0.5, 3 * half_width);
    const Eigen::Vector3d od = to_d(o), u = to_d(dir).normalized();

    // ray_cast_all: exactly the analytic set, at the analytic distances.
    const std::vector<RayHit> hits = world.ray_cast_all(o, dir, length, bodies_only());
    for (const Sphere& s : spheres) {
      double distance = 0;
      const Verdict v = analytic_cast(od, u, double(length), 0, s, distance);
      if (v == Verdict::Ambiguous) continue;
      const auto found = std::find_if(hits.begin(), hits.end(),
                                      [&](const RayHit& h) { return h.target.body == s.id; });
      if (v == Verdict::Miss) {
        EXPECT_EQ(found, hits.end()) << "ray " << q << " hit body " << s.id.index << " it misses";
        continue;
      }
      ++hits_seen;
      if (found == hits.end()) {
        ADD_FAILURE() << "ray " << q << " missed body " << s.id.index << " at " << distance << " m";
        continue;
      }
      EXPECT_NEAR(double(found->distance), distance, 1e-3 * std::max(1.0, distance));
    }
    for (std::size_t i = 1; i < hits.size(); ++i) EXPECT_LE(hits[i - 1].fraction, hits[i].fraction);

    // sphere_cast: the analytic closest (ties and near-ties left out).
    const Real radius = rng.uniform(0, 1.5);
    double best = 1e30, second = 1e30;
    const Sphere* closest = nullptr;
    bool ambiguous = false;
    for (const Sphere& s : spheres) {
      double distance = 0;
      const Verdict v = analytic_cast(od, u, double(length), double(radius), s, distance);
      ambiguous = ambiguous || v == Verdict::Ambiguous;
      if (v != Verdict::Hit) continue;
      if (distance < best) {
        second = best;
        best = distance;
        closest = &s;
      } else {
        second = std::min(second, distance);
      }
    }
    if (!ambiguous && second - best > kAmbiguous) {
      RayHit hit;
      const bool found = world.sphere_cast(o, radius, dir, length, bodies_only(), hit);
      EXPECT_EQ(found, closest != nullptr) << "sphere cast " << q;
      if (found && closest != nullptr) {
        EXPECT_EQ(hit.target.body, closest->id) << "sphere cast " << q;
        EXPECT_NEAR(double(hit.distance), best, 1e-3 * std::max(1.0, best));
      }
    }

    // overlap_sphere: exactly the analytic set, each once.
    const Real blast = rng.uniform(0, 4);
    const std::vector<ContactTarget> overlaps = world.overlap_sphere(o, blast, bodies_only());
    for (const Sphere& s : spheres) {
      const Verdict v = analytic_overlap(od, double(blast), s);
      if (v == Verdict::Ambiguous) continue;
      hits_seen += v == Verdict::Hit ? 1 : 0;
      const auto count = std::count_if(overlaps.begin(), overlaps.end(),
                                       [&](const ContactTarget& t) { return t.body == s.id; });
      EXPECT_EQ(count, v == Verdict::Hit ? 1 : 0) << "overlap " << q << " body " << s.id.index;
    }
  }
  return hits_seen;
}

/// Bodies of mixed sizes (a few huge), some in a tight cluster, moving.
std::vector<BodyId> random_scene(World& world, Lcg& rng, double half_width, int count) {
  std::vector<BodyId> ids;
  for (int i = 0; i < count; ++i) {
    const bool clustered = i % 3 == 0;
    const double spread = clustered ? half_width / 8 : half_width;
    BodyDef def = sphere_def(Vec3(rng.uniform(-spread, spread), rng.uniform(-spread, spread),
                                  rng.uniform(-spread, spread)),
                             i % 17 == 0 ? rng.uniform(3, 8) : rng.uniform(0.05, 1));
    def.linear_velocity = Vec3(rng.uniform(-20, 20), rng.uniform(-20, 20), rng.uniform(-20, 20));
    def.user_data = static_cast<std::uint64_t>(i);
    ids.push_back(add_body(world, def));
  }
  return ids;
}

TEST(QueryGrid, MatchesScanOfEveryBodyOnRandomScenes) {
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    SCOPED_TRACE(::testing::Message() << "seed " << seed);
    World world = make_world(space_def());
    Lcg rng(seed);
    const double half_width = 10 + 5 * double(seed % 4);
    std::vector<BodyId> ids = random_scene(world, rng, half_width, 40 + 30 * int(seed % 5));

    int seen = compare_with_scan(world, rng, half_width, 60);  // before any step
    ASSERT_TRUE(run(world, 3));
    seen += compare_with_scan(world, rng, half_width, 60);  // positions moved by the steps

    // Between steps: teleports, destructions and creations, each followed by queries.
    for (int k = 0; k < 10; ++k) {
      const BodyId moved = ids[static_cast<std::size_t>(k * 3) % ids.size()];
      RICOCHET_ASSERT_OK(world.set_transform(
          moved,
          Vec3(rng.uniform(-half_width, half_width), 0, rng.uniform(-half_width, half_width)),
          Quat::Identity()));
    }
    seen += compare_with_scan(world, rng, half_width, 40);
    for (int k = 0; k < 8; ++k) {
      RICOCHET_ASSERT_OK(world.destroy_body(ids.back()));
      ids.pop_back();
    }
    seen += compare_with_scan(world, rng, half_width, 40);
    const std::vector<BodyId> more = random_scene(world, rng, half_width * 2, 12);
    seen += compare_with_scan(world, rng, half_width * 2, 40);
    EXPECT_GT(seen, 100) << "the queries hardly hit anything: the comparison is empty";
  }
}

TEST(QueryGrid, FarFromOriginAndFarApart) {
  // Two groups 50 km apart, far from the origin: the grid must stay exact when coarse.
  World world = make_world(space_def());
  Lcg rng(99);
  for (int i = 0; i < 30; ++i) {
    const Real x = i % 2 == 0 ? Real(10000) : Real(60000);
    add_sphere(world, Vec3(x + rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-5, 5)),
               rng.uniform(0.3, 1));
  }
  RayHit hit;
  for (const Sphere& s : all_spheres(world)) {
    // Straight down onto a centre: that body, or one above it, is hit no later than its top.
    const Vec3 from = s.center.cast<Real>() + Vec3(0, 20, 0);
    ASSERT_TRUE(world.ray_cast_closest(from, Vec3(0, -1, 0), 40, bodies_only(), hit));
    EXPECT_LE(double(hit.distance), 20 - s.radius + 0.05);
  }
}

TEST(QueryUserData, InRayHitsSphereCastsOverlapsAndEvents) {
  World world = make_world(space_def());
  const ShapeId floor = add_floor(world, -5);
  BodyDef def = sphere_def(Vec3(0, 0, 0), 1);
  def.user_data = 0xC0FFEEu;
  const BodyId target = add_body(world, def);
  ASSERT_TRUE(run(world, 1));

  RayHit hit;
  ASSERT_TRUE(world.ray_cast_closest(Vec3(-5, 0, 0), Vec3(1, 0, 0), 10, {}, hit));
  EXPECT_EQ(hit.target.body, target);
  EXPECT_EQ(hit.target.user_data, 0xC0FFEEu);
  ASSERT_TRUE(world.sphere_cast(Vec3(-5, 0, 0), Real(0.5), Vec3(1, 0, 0), 10, {}, hit));
  EXPECT_EQ(hit.target.user_data, 0xC0FFEEu);
  ASSERT_TRUE(world.ray_cast_closest(Vec3(3, 0, 0), Vec3(0, -1, 0), 10, {}, hit));
  EXPECT_EQ(hit.target.shape, floor);
  EXPECT_EQ(hit.target.user_data, 0u);
  const std::vector<ContactTarget> overlaps = world.overlap_sphere(Vec3(1, 1, 0), 1, {});
  ASSERT_EQ(overlaps.size(), 1u);
  EXPECT_EQ(overlaps[0].user_data, 0xC0FFEEu);

  // A projectile hit names the body's user_data beside its own.
  ProjectileDef shot;
  shot.position = Vec3(-5, 0, 0);
  shot.velocity = Vec3(300, 0, 0);
  shot.gravity_scale = 0;
  shot.user_data = 7;
  ASSERT_TRUE(world.create_projectile(shot).ok());
  ASSERT_TRUE(run(world, 1));
  ASSERT_EQ(world.projectile_hit_events().size(), 1u);
  EXPECT_EQ(world.projectile_hit_events()[0].user_data, 7u);
  EXPECT_EQ(world.projectile_hit_events()[0].target.user_data, 0xC0FFEEu);

  // Contact events carry both bodies' user_data.
  BodyDef other = sphere_def(Vec3(3, 0, 0), 1);
  other.linear_velocity = Vec3(-30, 0, 0);
  other.user_data = 55;
  const BodyId bullet = add_body(world, other);
  bool begun = false;
  for (int i = 0; i < 10 && !begun; ++i) {
    ASSERT_TRUE(run(world, 1));
    for (const ContactBeginEvent& e : world.contact_begin_events()) {
      if (e.other.body.is_null()) continue;
      begun = true;
      const bool target_first = e.body == target;
      EXPECT_EQ(e.user_data, target_first ? 0xC0FFEEu : 55u);
      EXPECT_EQ(e.other.user_data, target_first ? 55u : 0xC0FFEEu);
      EXPECT_TRUE(target_first ? e.other.body == bullet : e.body == bullet);
    }
  }
  EXPECT_TRUE(begun) << "the bodies never touched";
}

TEST(LagCompensation, ShotAtPastPositionHitsProxyAndMissesLiveWorld) {
  World world = make_world(space_def());
  add_plane(world, Vec3(1, 0, 0), -50);  // a wall behind the target: solid for x < -50
  const ShapeId floor = add_floor(world, -2);
  BodyDef runner = sphere_def(Vec3(0, 0, 0), Real(0.4));
  runner.linear_velocity = Vec3(0, 0, 10);  // 10 m/s across the line of fire
  runner.user_data = 1234;
  const BodyId target = add_body(world, runner);
  const Vec3 seen_at = state_of(world, target).position;
  ASSERT_TRUE(run(world, 6));  // 100 ms: the runner is now 1 m further, past its own width
  ASSERT_GT(double(state_of(world, target).position.z()), 0.9);

  const std::uint64_t hash = world.state_hash();
  const Vec3 muzzle(20, 0, 0), aim(-1, 0, 0);
  RayHit live;
  QueryFilter filter;
  const bool live_hit = world.ray_cast_closest(muzzle, aim, 100, filter, live);
  EXPECT_TRUE(!live_hit || live.target.body != target) << "the live world already has it there";

  const std::vector<SphereProxy> past = {{seen_at, Real(0.4), target, 1234}};
  filter.bodies = false;  // the proxy stands in for the live body
  RayHit rewound;
  ASSERT_TRUE(world.ray_cast_spheres(muzzle, aim, 100, filter, past, rewound));
  EXPECT_EQ(rewound.target.body, target);
  EXPECT_EQ(rewound.target.user_data, 1234u);
  EXPECT_NEAR(double(rewound.distance), 20 - 0.4, 1e-4);
  EXPECT_TRUE(near(rewound.normal, Vec3(1, 0, 0), 1e-4));
  ASSERT_TRUE(world.sphere_cast_spheres(muzzle, Real(0.1), aim, 100, filter, past, rewound));
  EXPECT_NEAR(double(rewound.distance), 20 - 0.5, 1e-4);

  // A wall in front still stops the shot; the shooter's own proxy is skipped.
  const std::vector<SphereProxy> behind_floor = {{Vec3(5, Real(-3.5), 0), 1, target, 1}};
  ASSERT_TRUE(
      world.ray_cast_spheres(Vec3(5, 0, 0), Vec3(0, -1, 0), 10, filter, behind_floor, rewound));
  EXPECT_EQ(rewound.target.shape, floor);
  filter.ignore = target;
  EXPECT_FALSE(world.ray_cast_spheres(muzzle, aim, 30, filter, past, rewound));

  EXPECT_EQ(world.state_hash(), hash) << "a query changed the simulation state";
  EXPECT_FALSE(state_of(world, target).sleeping);
}

TEST(LagCompensation, InvalidProxiesAreSkipped) {
  World world = make_world(space_def());
  const std::vector<SphereProxy> proxies = {
      {Vec3(5, 0, 0), 0, BodyId{}, 1},
      {Vec3(6, 0, 0), -1, BodyId{}, 2},
      {Vec3(kNaN, 0, 0), 1, BodyId{}, 3},
      {Vec3(9, 0, 0), 1, BodyId{}, 4},
  };
  RayHit hit;
  ASSERT_TRUE(world.ray_cast_spheres(Vec3::Zero(), Vec3(1, 0, 0), 20, {}, proxies, hit));
  EXPECT_EQ(hit.target.user_data, 4u);
  EXPECT_NEAR(double(hit.distance), 8, 1e-5);
}

}  // namespace
}  // namespace ricochet::physics::test::query_test
