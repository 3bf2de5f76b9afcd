// Newton's cradle: a row of touching, equal, frictionless spheres with restitution 1, struck at
// one end. Pairwise elastic collisions hand the striker's momentum and energy down the row, so
// only the far end leaves, at the striker's speed; k strikers send off k balls. A solver that
// resolves the row as one simultaneous contact spreads the impulse instead (Bullet 3.24 sends the
// striker back at −0.59 v and the rest forward at 0.40 v).

#include "test_util.h"

namespace ricochet::physics::test::cradle_test {
namespace {

constexpr Real kRadius = Real(0.5);
constexpr Real kSpeed = 5;  // m/s, well above the 1 m/s restitution threshold

struct CradleSetup {
  int balls = 5;             ///< in the row, touching
  int strikers = 1;          ///< touching each other, at kSpeed, kGap before the row
  std::vector<Real> masses;  ///< per ball (row then strikers); empty: all 1 kg
  PositionCorrection correction = PositionCorrection::Baumgarte;
  bool wide_simd = true;
  int iterations = 10;
};

struct CradleResult {
  std::vector<double> v;  ///< final x velocity per ball, from the far end of the strikers
  double energy = 0;      ///< J
  double energy0 = 0;     ///< J
};

/// Strikers first (leftmost first), then the row; centres 2r apart within each group, the
/// strikers' leading surface 0.3 m from the row.
CradleResult run_cradle(const CradleSetup& setup) {
  WorldDef def = with_correction(space_def(), setup.correction);
  def.wide_simd = setup.wide_simd;
  def.iterations = setup.iterations;
  World world = make_world(def);
  const int n = setup.strikers + setup.balls;
  std::vector<BodyId> ids;
  CradleResult r;
  for (int i = 0; i < n; ++i) {
    const bool striker = i < setup.strikers;
    const double x = striker ? -0.3 - 2 * double(kRadius) * (setup.strikers - i)
                             : 2 * double(kRadius) * (i - setup.strikers);
    const Real mass = setup.masses.empty() ? Real(1) : setup.masses[std::size_t(i)];
    BodyDef body = sphere_def(Vec3(Real(x), 0, 0), kRadius, mass, material(1, 0));
    if (striker) body.linear_velocity = Vec3(kSpeed, 0, 0);
    r.energy0 += striker ? 0.5 * double(mass) * double(kSpeed) * double(kSpeed) : 0;
    ids.push_back(add_body(world, body));
  }
  run_or_throw(world, 60);  // 1 s; the strike comes at about 0.06 s
  for (const BodyId id : ids) {
    const BodyState s = state_of(world, id);
    r.v.push_back(double(s.linear_velocity.x()));
    r.energy += kinetic_energy(s);
  }
  return r;
}

std::string describe(const CradleResult& r) {
  std::ostringstream out;
  out << "v/v0:";
  for (const double v : r.v) out << ' ' << v / double(kSpeed);
  out << "; energy kept " << r.energy / r.energy0;
  return out.str();
}

class CradleTest : public ::testing::TestWithParam<PositionCorrection> {};

/// k strikers into a row: the last k balls leave at v0, the others are at rest, energy is kept.
void expect_cradle(int strikers, int balls, PositionCorrection correction) {
  CradleSetup setup;
  setup.strikers = strikers;
  setup.balls = balls;
  setup.correction = correction;
  const CradleResult r = run_cradle(setup);
  const int n = strikers + balls;
  for (int i = 0; i < n; ++i) {
    const double expected = i >= n - strikers ? double(kSpeed) : 0.0;
    EXPECT_NEAR(r.v[std::size_t(i)], expected, 0.02 * double(kSpeed))
        << "ball " << i << " of " << n << ", " << correction_name(correction) << ": "
        << describe(r);
  }
  EXPECT_NEAR(r.energy / r.energy0, 1.0, 0.02) << describe(r);
}

TEST_P(CradleTest, ThreeBalls) {
  expect_cradle(1, 2, GetParam());
}
TEST_P(CradleTest, FiveBalls) {
  expect_cradle(1, 4, GetParam());
}
TEST_P(CradleTest, SevenBalls) {
  expect_cradle(1, 6, GetParam());
}
TEST_P(CradleTest, TwoStrikeThree) {
  expect_cradle(2, 3, GetParam());
}

TEST_P(CradleTest, UnequalMassesFollowPairwiseCollisions) {
  // 1 kg strikes touching 2 kg and 4 kg. In sequence: 1 on 2 gives −v/3 and 2v/3; 2 on 4 gives
  // −2v/9 and 4v/9. The 2 kg ball then recedes more slowly than the 1 kg one: no third impact.
  CradleSetup setup;
  setup.strikers = 1;
  setup.balls = 2;
  setup.masses = {1, 2, 4};
  setup.correction = GetParam();
  const CradleResult r = run_cradle(setup);
  const double v = kSpeed;
  const double tol = 0.02 * v;
  EXPECT_NEAR(r.v[0], -v / 3, tol) << describe(r);
  EXPECT_NEAR(r.v[1], -2 * v / 9, tol) << describe(r);
  EXPECT_NEAR(r.v[2], 4 * v / 9, tol) << describe(r);
  EXPECT_NEAR(r.energy / r.energy0, 1.0, 0.02) << describe(r);
}

TEST(Cradle, BothSimdPathsAgreeBitForBit) {
  CradleSetup setup;
  setup.strikers = 2;
  setup.balls = 5;
  const CradleResult wide = run_cradle(setup);
  setup.wide_simd = false;
  const CradleResult narrow = run_cradle(setup);
  EXPECT_EQ(wide.v, narrow.v);
}

INSTANTIATE_TEST_SUITE_P(AllCorrections, CradleTest, ::testing::ValuesIn(kAllCorrections),
                         [](const ::testing::TestParamInfo<PositionCorrection>& info) {
                           return std::string(correction_name(info.param));
                         });

}  // namespace
}  // namespace ricochet::physics::test::cradle_test
