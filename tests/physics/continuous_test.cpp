// Continuous collision: a 5 cm (diameter) sphere flagged fast at 1000 m/s covers 16.7 m per
// 60 Hz step, 670 times its own diameter, so without swept tests it would jump straight over a
// 1 cm wall. For many start offsets (covering a whole step length, so the wall falls at every
// phase of a step) and approach angles it must never get through.
//
// "Through" is judged on the straight segment between consecutive step positions: crossing the
// wall's mid-plane inside the wall's face is a tunnel; going round the wall's edge is not. The
// centre must also never sink into the wall deeper than linear_slop (+1 mm for rounding and
// for a time-of-impact solver's stopping tolerance).

#include <functional>

#include "test_util.h"

namespace ricochet::physics::test::continuous_test {
namespace {

constexpr Real kFastRadius = Real(0.025);
constexpr Real kSpeed = 1000;

WorldDef fast_def() {
  WorldDef def = space_def();
  def.enable_continuous = true;
  return def;
}

BodyDef fast_sphere(const Vec3& position, const Vec3& velocity) {
  BodyDef def = sphere_def(position, kFastRadius, Real(0.065), material(0, 0));
  def.linear_velocity = velocity;
  def.fast = true;
  return def;
}

/// Directions towards +x, up to 45° off the wall normal, in several planes.
std::vector<Vec3> approach_directions() {
  std::vector<Vec3> dirs;
  const double deg = EIGEN_PI / 180;
  for (double theta : {0.0, 10.0, 30.0, 45.0}) {
    for (double phi : {0.0, 100.0, 230.0}) {
      if (theta == 0 && phi != 0) continue;
      const double t = theta * deg, p = phi * deg;
      dirs.emplace_back(Real(std::cos(t)), Real(std::sin(t) * std::cos(p)),
                        Real(std::sin(t) * std::sin(p)));
    }
  }
  return dirs;
}

/// Runs one shot at a wall whose face is the square |y|, |z| < 1 at x = 0, half thickness
/// `half_thickness`, aimed at `target` on the face from `distance` away. Returns a failure
/// description, or an empty string.
std::string shoot(World& world, const Vec3& target, const Vec3& dir, Real distance,
                  Real half_thickness) {
  const BodyId id = add_body(world, fast_sphere(target - dir * distance, dir * kSpeed));
  const double per_step = double(kSpeed) * double(kDt60);
  const int steps = int(std::ceil(double(distance) / per_step)) + 2;
  const double deepest =
      -double(half_thickness) - double(kFastRadius) + double(world.definition().linear_slop) + 1e-3;
  Vec3 prev = state_of(world, id).position;
  for (int i = 0; i < steps; ++i) {
    run_or_throw(world, 1);
    const BodyState s = state_of(world, id);
    if (!is_finite(s)) return cat("non-finite state at step ", i);
    const Vec3 cur = s.position;
    if (prev.x() < 0 && cur.x() >= 0) {
      const Real f = -prev.x() / (cur.x() - prev.x());
      const Vec3 cross = prev + f * (cur - prev);
      if (std::abs(cross.y()) < 1 && std::abs(cross.z()) < 1) {
        return cat("tunnelled at step ", i, ", crossing at y ", cross.y(), " z ", cross.z());
      }
    }
    if (std::abs(cur.y()) < 1 && std::abs(cur.z()) < 1 && cur.x() < 0 && cur.x() > deepest) {
      return cat("centre ", cur.x(), " inside the wall at step ", i);
    }
    prev = cur;
  }
  const BodyState s = state_of(world, id);
  // Still in front of the face (it did not slide off an edge): it is resting against the wall,
  // so with e = 0 its normal velocity is gone.
  if (std::abs(s.position.y()) < 1 && std::abs(s.position.z()) < 1 && s.linear_velocity.x() > 1) {
    return cat("still moving into the wall at ", s.linear_velocity.x(), " m/s");
  }
  // Head-on and frictionless against a flat wall: nothing can create sideways velocity (a contact
  // normal taken from an internal mesh edge instead of the face would).
  if (dir.x() == 1) {
    const double sideways =
        std::hypot(double(s.linear_velocity.y()), double(s.linear_velocity.z()));
    if (sideways > 1) return cat("head-on shot deflected sideways at ", sideways, " m/s");
  }
  return {};
}

void sweep_offsets_and_angles(const std::function<void(World&)>& add_wall, Real half_thickness) {
  const std::vector<Vec3> dirs = approach_directions();
  int shots = 0, failures = 0;
  for (int k = 0; k < 46; ++k) {
    const Real distance = Real(0.3 + 0.37 * k);  // 0.3 m .. 16.95 m: one full step of travel
    for (std::size_t d = 0; d < dirs.size(); ++d) {
      World world = make_world(fast_def());
      add_wall(world);
      const Vec3 target(0, Real(0.4 * std::sin(k * 1.3)), Real(0.4 * std::cos(k * 0.7)));
      const std::string failure = shoot(world, target, dirs[d], distance, half_thickness);
      ++shots;
      if (!failure.empty()) {
        ++failures;
        if (failures <= 10) {
          ADD_FAILURE() << "distance " << distance << " direction (" << dirs[d].transpose()
                        << "): " << failure;
        }
      }
    }
  }
  EXPECT_EQ(failures, 0) << "of " << shots << " shots";
}

TEST(Continuous, FastSphereNeverTunnelsThroughThinBox) {
  // 1 cm thick static box: half_extents.x = 0.005, face 2 m × 2 m.
  sweep_offsets_and_angles(
      [](World& world) { add_box(world, Vec3::Zero(), Vec3(Real(0.005), 1, 1)); }, Real(0.005));
}

TEST(Continuous, FastSphereNeverTunnelsThroughMeshWall) {
  // Two triangles spanning the square |y|, |z| <= 1 in the plane x = 0: zero thickness.
  sweep_offsets_and_angles(
      [](World& world) {
        add_mesh(world, {Vec3(0, -1, -1), Vec3(0, 1, -1), Vec3(0, 1, 1), Vec3(0, -1, 1)},
                 {0, 1, 2, 0, 2, 3});
      },
      0);
}

TEST(Continuous, FastSpheresHeadOnCollide) {
  // Two fast spheres at ±1000 m/s close at 2000 m/s, 33 m per step. For gaps covering a whole
  // step they must meet: never swap order along x, and their velocities change (e = 0: they
  // stop each other; 10 m/s allows for any residual).
  int failures = 0;
  for (int k = 0; k < 40; ++k) {
    const Real gap = Real(0.2 + 0.85 * k);  // up to 33.4 m
    World world = make_world(fast_def());
    const BodyId a = add_body(world, fast_sphere(Vec3(-gap / 2, 0, 0), Vec3(kSpeed, 0, 0)));
    const BodyId b = add_body(world, fast_sphere(Vec3(gap / 2, 0, 0), Vec3(-kSpeed, 0, 0)));
    const int steps = int(std::ceil(double(gap) / (2 * double(kSpeed) * double(kDt60)))) + 2;
    for (int i = 0; i < steps; ++i) {
      ASSERT_TRUE(run(world, 1));
      const BodyState sa = state_of(world, a), sb = state_of(world, b);
      ASSERT_TRUE(is_finite(sa) && is_finite(sb));
      if (sa.position.x() >= sb.position.x()) {
        ++failures;
        ADD_FAILURE() << "gap " << gap << ": passed through each other at step " << i;
        break;
      }
    }
    const BodyState sa = state_of(world, a), sb = state_of(world, b);
    EXPECT_LT(std::abs(sa.linear_velocity.x()), 10) << "gap " << gap;
    EXPECT_LT(std::abs(sb.linear_velocity.x()), 10) << "gap " << gap;
    EXPECT_GE(sb.position.x() - sa.position.x(),
              2 * double(kFastRadius) - double(world.definition().linear_slop) - 1e-3)
        << "gap " << gap;
    if (failures > 5) break;
  }
}

TEST(Continuous, FastSpheresGlancingStillCollide) {
  // Offset sideways by less than the sum of the radii (0.05 m): they must touch and deflect.
  for (Real offset : {Real(0.01), Real(0.03), Real(0.045)}) {
    for (Real gap : {Real(1), Real(17), Real(29.5)}) {
      World world = make_world(fast_def());
      const BodyId a = add_body(world, fast_sphere(Vec3(-gap / 2, 0, 0), Vec3(kSpeed, 0, 0)));
      const BodyId b = add_body(world, fast_sphere(Vec3(gap / 2, offset, 0), Vec3(-kSpeed, 0, 0)));
      ASSERT_TRUE(run(world, 4));
      const BodyState sa = state_of(world, a), sb = state_of(world, b);
      ASSERT_TRUE(is_finite(sa) && is_finite(sb));
      // A collision along a normal with a y component gives A downward, B upward velocity.
      EXPECT_LT(sa.linear_velocity.y(), -1) << "offset " << offset << " gap " << gap;
      EXPECT_GT(sb.linear_velocity.y(), 1) << "offset " << offset << " gap " << gap;
      EXPECT_LT(sa.linear_velocity.x(), kSpeed - 1) << "offset " << offset << " gap " << gap;
    }
  }
}

}  // namespace
}  // namespace ricochet::physics::test::continuous_test
