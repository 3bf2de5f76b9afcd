// Determinism: the same inputs give bit-identical states, in any number of worlds, every time.

#include "test_util.h"

namespace ricochet::physics::test::determinism_test {
namespace {

#if defined(NDEBUG)
constexpr int kRainBodies = 200;
#else
constexpr int kRainBodies = 64;  // Debug + sanitizers: same scene, fewer spheres
#endif
constexpr int kRainSteps = 300;

/// A vector with each component uniform in ±half_range, drawn x, then y, then z.
Vec3 random_vec(Lcg& rng, const Vec3& half_range) {
  const Real x = rng.uniform(-half_range.x(), half_range.x());
  const Real y = rng.uniform(-half_range.y(), half_range.y());
  const Real z = rng.uniform(-half_range.z(), half_range.z());
  return Vec3(x, y, z);
}

/// Spheres on a jittered grid above a floor inside four walls, with some initial velocities and
/// mixed sizes, masses and materials; sleeping on (default WorldDef) so sleep is covered too.
World build_rain(int count, std::vector<BodyId>& ids, const WorldDef& def = WorldDef{}) {
  World world = make_world(def);
  const Material m = material(Real(0.2), Real(0.5));
  add_floor(world, 0, m);
  const Real wall = 4;
  add_plane(world, Vec3::UnitX(), -wall, m);
  add_plane(world, -Vec3::UnitX(), -wall, m);
  add_plane(world, Vec3::UnitZ(), -wall, m);
  add_plane(world, -Vec3::UnitZ(), -wall, m);
  Lcg rng(2024);
  const int side = 6;
  for (int i = 0; i < count; ++i) {
    const int x = i % side, z = (i / side) % side, y = i / (side * side);
    // One draw per statement: the order in which a call's arguments are evaluated is
    // unspecified (GCC goes right to left, clang left to right), and the scene, so the golden
    // hash below, must not depend on the compiler.
    const double jitter_x = 0.05 * rng.next();
    const double jitter_z = 0.05 * rng.next();
    const Real radius = rng.uniform(0.3, 0.5);
    const Real mass = rng.uniform(0.5, 3.0);
    const Real restitution = rng.uniform(0, 0.5);
    const Real friction = rng.uniform(0.2, 0.8);
    const Real rolling = rng.uniform(0, 0.02);
    BodyDef def = sphere_def(
        Vec3(Real(-3.0 + 1.2 * x + jitter_x), Real(0.6 + 1.2 * y), Real(-3.0 + 1.2 * z + jitter_z)),
        radius, mass, material(restitution, friction, rolling));
    def.linear_velocity = random_vec(rng, Vec3(2, 1, 2));
    def.angular_velocity = random_vec(rng, Vec3(3, 3, 3));
    def.inertia = i % 4 == 0 ? InertiaModel::HollowSphere : InertiaModel::SolidSphere;
    ids.push_back(add_body(world, def));
  }
  return world;
}

/// Identical edits applied to a world mid-run: destroy some bodies, create others (slot reuse),
/// push a few.
void churn(World& world, std::vector<BodyId>& ids) {
  for (std::size_t i = 0; i < ids.size(); i += 7) check(world.destroy_body(ids[i]), "destroy_body");
  for (std::size_t i = 0; i < ids.size(); i += 7) {
    ids[i] = add_sphere(world, Vec3(Real(-2 + 0.5 * double(i % 9)), 12, 0), Real(0.4), 1);
  }
  for (std::size_t i = 3; i < ids.size(); i += 11) {
    check(world.apply_impulse(ids[i], Vec3(1, 2, 0),
                              state_of(world, ids[i]).position + Vec3(0, Real(0.1), 0)),
          "apply_impulse");
  }
}

TEST(Determinism, TwoWorldsStepIdentically) {
  std::vector<BodyId> ids_a, ids_b;
  World a = build_rain(kRainBodies, ids_a);
  World b = build_rain(kRainBodies, ids_b);
  ASSERT_EQ(a.state_hash(), b.state_hash()) << "freshly built worlds differ";
  for (int i = 0; i < kRainSteps; ++i) {
    if (i == 100) {
      churn(a, ids_a);
      churn(b, ids_b);
      ASSERT_EQ(ids_a, ids_b) << "handle allocation is not deterministic";
    }
    ASSERT_TRUE(run(a, 1));
    // Queries are const: running them on one world only must not change its future.
    RayHit hit;
    (void)a.ray_cast_closest(Vec3(0, 20, 0), Vec3(0, -1, 0), 30, {}, hit);
    (void)a.overlap_sphere(Vec3(0, 1, 0), 2, {});
    ASSERT_TRUE(run(b, 1));
    ASSERT_EQ(a.state_hash(), b.state_hash()) << "diverged at step " << i;
  }
  EXPECT_EQ(a.step_count(), std::uint64_t(kRainSteps));
  for (std::size_t k = 0; k < ids_a.size(); ++k) {
    EXPECT_TRUE(same_state(state_of(a, ids_a[k]), state_of(b, ids_b[k]))) << "body " << k;
  }
}

TEST(Determinism, RunToCompletionEqualsInterleaved) {
  // A third world run alone, start to finish, ends where the interleaved pair ended: no shared
  // state between worlds.
  std::vector<BodyId> ids_a, ids_b, ids_c;
  World a = build_rain(kRainBodies / 2, ids_a);
  World b = build_rain(kRainBodies / 2, ids_b);
  for (int i = 0; i < 120; ++i) {
    ASSERT_TRUE(run(a, 1));
    ASSERT_TRUE(run(b, 1));
  }
  World c = build_rain(kRainBodies / 2, ids_c);
  ASSERT_TRUE(run(c, 120));
  EXPECT_EQ(a.state_hash(), b.state_hash());
  EXPECT_EQ(a.state_hash(), c.state_hash());
}

TEST(Determinism, HashSeesEveryChange) {
  std::vector<BodyId> ids_a, ids_b;
  World a = build_rain(20, ids_a);
  World b = build_rain(20, ids_b);
  ASSERT_TRUE(run(a, 10));
  ASSERT_TRUE(run(b, 10));
  ASSERT_EQ(a.state_hash(), b.state_hash());
  // One ulp of one velocity component of one body changes the hash.
  const BodyState s = state_of(b, ids_b[13]);
  Vec3 v = s.linear_velocity;
  v.x() = std::nextafter(v.x(), Real(1e9));
  RICOCHET_ASSERT_OK(b.set_linear_velocity(ids_b[13], v));
  EXPECT_NE(a.state_hash(), b.state_hash());
  // So does the step counter alone (an empty world stepped once more).
  World e1 = make_world();
  World e2 = make_world();
  ASSERT_TRUE(run(e2, 1));
  EXPECT_NE(e1.state_hash(), e2.state_hash());
}

TEST(Determinism, WideAndBaselineSimdAgreeBitForBit) {
  // The contact solver runs AVX2 code when the CPU has it and SSE2/NEON code otherwise; every
  // solver variant (position correction, substeps, rolling) must end in the same state on both.
#if defined(__x86_64__)
  if (!__builtin_cpu_supports("avx2")) GTEST_SKIP() << "CPU without AVX2: only one path exists";
#else
  GTEST_SKIP() << "not x86-64: only the baseline path exists";
#endif
  struct Variant {
    PositionCorrection method;
    int substeps;
    bool rotation, friction;
  };
  const Variant variants[] = {
      {PositionCorrection::Baumgarte, 1, true, true},
      {PositionCorrection::Baumgarte, 4, true, true},
      {PositionCorrection::SplitImpulse, 1, true, true},
      {PositionCorrection::SplitImpulse, 4, true, true},
      {PositionCorrection::SoftStep, 1, true, true},
      {PositionCorrection::SoftStep, 4, true, true},
      {PositionCorrection::Baumgarte, 1, false, true},  // linear friction kernel
      {PositionCorrection::SoftStep, 4, true, false},   // normal-only kernel
  };
  for (const Variant& v : variants) {
    {
      const PositionCorrection method = v.method;
      const int substeps = v.substeps;
      WorldDef def;
      def.position_correction = method;
      def.substeps = substeps;
      def.enable_rotation = v.rotation;
      def.enable_friction = v.friction;
      std::vector<BodyId> ids_wide, ids_baseline;
      def.wide_simd = true;
      World wide = build_rain(kRainBodies / 2, ids_wide, def);
      def.wide_simd = false;
      World baseline = build_rain(kRainBodies / 2, ids_baseline, def);
      ASSERT_TRUE(run(wide, 90));
      ASSERT_TRUE(run(baseline, 90));
      EXPECT_EQ(wide.state_hash(), baseline.state_hash())
          << "method " << int(method) << ", substeps " << substeps << ", rotation " << v.rotation
          << ", friction " << v.friction;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Golden hash: the exact state after a fixed scene and step count, pinned so that any change to
// the simulation's arithmetic (or a compiler/flag change that breaks bit-reproducibility) is
// noticed. The values are specific to this scene, to float vs double (RICOCHET_DOUBLE) and to
// x86-64 with -ffp-contract=off. The same value holds at -O3 and at -O0 with sanitizers.
//
// When the simulation changes on purpose, the failure message prints the new value: review the
// change, then record it here in the same commit.
#if defined(RICOCHET_DOUBLE)
constexpr std::uint64_t kGoldenHash = 0xbe06762dde7ef1bbull;
#else
constexpr std::uint64_t kGoldenHash = 0xc7ccd2334d8271d5ull;
#endif

TEST(Determinism, GoldenHash) {
  // Small and fixed in every build type (the same constant must hold in Release and Debug).
  std::vector<BodyId> ids;
  World world = build_rain(64, ids);
  ASSERT_TRUE(run(world, 120));
  const std::uint64_t actual = world.state_hash();
  EXPECT_EQ(actual, kGoldenHash) << "golden state hash mismatch: actual " << hex(actual) << " ("
                                 << actual << "ull), expected " << hex(kGoldenHash)
                                 << (kDoublePrecision ? " [double]" : " [float]");
}

}  // namespace
}  // namespace ricochet::physics::test::determinism_test
