// A sphere dropped on a plane rebounds to h·e² (energy after impact e² of the energy before),
// and an elastic ball keeps its height bounce after bounce.
//
// Restitution takes the impact's phase inside the step into account (see apply_restitution), so
// the rebound peak is exact for constant gravity up to round-off and the sampling of the peak:
// the highest sampled height is at most g·dt²/8 below the true apex.

#include "test_util.h"

namespace ricochet::physics::test {
namespace {

constexpr Real kBounceDt = Real(1) / 240;

struct BounceMeasure {
  double impact_speed = 0;   ///< largest downward speed before the bounce
  double rebound_speed = 0;  ///< first upward speed after the bounce
  double peak = -1;          ///< highest bottom height after the bounce, above the plane
  bool bounced = false;
  bool finished = false;
};

BounceMeasure drop(Real h, Real e) {
  World world = make_world();  // default gravity, sleeping off
  add_floor(world, 0, material(0, 0));
  const Real r = Real(0.5);
  const BodyId id = add_sphere(world, Vec3(0, h + r, 0), r, 1, material(e, 0));
  BounceMeasure m;
  for (int i = 0; i < steps_for(4.0, kBounceDt); ++i) {
    run_or_throw(world, 1, kBounceDt);
    const BodyState s = state_of(world, id);
    const double vy = s.linear_velocity.y();
    if (!m.bounced) {
      if (vy > 0) {
        m.bounced = true;
        m.rebound_speed = vy;
        m.peak = double(s.position.y()) - r;
      } else {
        m.impact_speed = std::max(m.impact_speed, -vy);
      }
    } else {
      m.peak = std::max(m.peak, double(s.position.y()) - r);
      if (vy <= 0) {
        m.finished = true;
        break;
      }
    }
  }
  return m;
}

class BounceTest : public ::testing::TestWithParam<double> {};

TEST_P(BounceTest, ReboundHeightIsHTimesESquared) {
  const Real e = Real(GetParam());
  const Real h = 2;
  const BounceMeasure m = drop(h, e);
  ASSERT_TRUE(m.bounced) << "no bounce for e = " << e;
  ASSERT_TRUE(m.finished) << "no peak within 4 s";
  const double g = double(kGravity);
  const double v_i = std::sqrt(2 * g * double(h));
  // Impact and rebound speeds: within two g·dt (one for the step the contact is resolved in, one
  // for the semi-implicit speed at a given height).
  EXPECT_NEAR(m.impact_speed, v_i, 2 * g * double(kBounceDt) + 0.01 * v_i);
  EXPECT_NEAR(m.rebound_speed, double(e) * v_i, 2 * g * double(kBounceDt) + 0.01 * v_i);
  const double expected = double(h) * double(e) * double(e);
  const double sampling = g * double(kBounceDt) * double(kBounceDt) / 8;
  EXPECT_NEAR(m.peak, expected, 1e-3 * double(h) + sampling) << "e = " << e;
}

INSTANTIATE_TEST_SUITE_P(Restitutions, BounceTest, ::testing::Values(0.5, 0.8, 1.0),
                         [](const ::testing::TestParamInfo<double>& info) {
                           std::string name = "e";
                           name += std::to_string(int(std::lround(info.param * 100)));
                           return name;
                         });

/// Apex of each of the first `bounces` upward flights of a ball dropped from `h` onto a floor,
/// both with restitution 1: the vertex of the parabola through the three highest samples.
std::vector<double> elastic_apexes(Real h, Real dt, const WorldDef& def, int bounces) {
  World world = make_world(def);
  add_floor(world, 0, material(1, 0));
  const Real r = Real(0.5);
  const BodyId id = add_sphere(world, Vec3(0, h + r, 0), r, 1, material(1, 0));
  std::vector<double> apexes;
  double before = double(h), last = double(h);
  bool rising = false;
  const int steps = steps_for(3 * bounces * std::sqrt(2 * double(h) / double(kGravity)), dt);
  for (int i = 0; i < steps && int(apexes.size()) < bounces; ++i) {
    run_or_throw(world, 1, dt);
    const double height = double(state_of(world, id).position.y() - r);
    if (height > last) {
      rising = true;
    } else if (rising) {
      const double curvature = before - 2 * last + height;
      apexes.push_back(last - (height - before) * (height - before) / (8 * curvature));
      rising = false;
    }
    before = last;
    last = height;
  }
  return apexes;
}

class ElasticBounceTest
    : public ::testing::TestWithParam<std::tuple<Integrator, PositionCorrection>> {};

TEST_P(ElasticBounceTest, KeepsItsHeightWithinOnePercentOverTwentyBounces) {
  WorldDef def = awake_def();
  def.integrator = std::get<0>(GetParam());
  def.position_correction = std::get<1>(GetParam());
  const Real h = 10;
  const std::vector<double> apexes = elastic_apexes(h, Real(1) / 60, def, 20);
  ASSERT_EQ(apexes.size(), 20u);
  for (std::size_t k = 0; k < apexes.size(); ++k)
    EXPECT_NEAR(apexes[k], double(h), 0.01 * double(h)) << "bounce " << k + 1;
}

INSTANTIATE_TEST_SUITE_P(IntegratorsAndCorrections, ElasticBounceTest,
                         ::testing::Combine(::testing::Values(Integrator::SemiImplicitEuler,
                                                              Integrator::ExactBallistic,
                                                              Integrator::Rk4),
                                            ::testing::Values(PositionCorrection::Baumgarte,
                                                              PositionCorrection::SplitImpulse,
                                                              PositionCorrection::SoftStep)));

TEST(Bounce, ImpactSlowerThanRestitutionThresholdDoesNotBounce) {
  // Dropped from 2 cm the impact speed is sqrt(2·g·0.02) = 0.63 m/s < restitution_threshold
  // (1 m/s), so even e = 0.8 must not bounce: an upward speed above 0.1 m/s would be a bounce
  // (e·v would be 0.5 m/s); below that is position correction at most.
  World world = make_world();
  add_floor(world, 0, material(0, 0));
  const Real r = Real(0.5);
  const BodyId id = add_sphere(world, Vec3(0, Real(0.02) + r, 0), r, 1, material(Real(0.8), 0));
  double max_up = 0;
  for (int i = 0; i < 120; ++i) {
    ASSERT_TRUE(run(world, 1, kBounceDt));
    max_up = std::max(max_up, double(state_of(world, id).linear_velocity.y()));
  }
  EXPECT_LT(max_up, 0.1);
  const BodyState s = state_of(world, id);
  EXPECT_NEAR(s.position.y(), r, 1e-3);  // resting, within the resting-contact bound
}

}  // namespace
}  // namespace ricochet::physics::test
