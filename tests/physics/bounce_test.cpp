// A sphere dropped on a plane rebounds to h·e² (energy after impact e² of the energy before),
// and an elastic ball keeps its height bounce after bounce.
//
// Restitution takes the impact's phase inside the step into account (see apply_restitution), so
// the rebound peak is exact for constant gravity up to round-off and the sampling of the peak:
// the highest sampled height is at most g·dt²/8 below the true apex.

#include "test_util.h"

namespace ricochet::physics::test::bounce_test {
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

/// The apex of the free flight a ball starts when released at rest from `h`, as the integrator
/// sees it. Semi-implicit Euler stores the mean velocity over the step just taken, so v = 0 at
/// release is a true velocity of +½·g·dt: its positions lie on a parabola whose vertex is
/// g·dt²/8 above h (3.4·10⁻⁵·h for h = 10 m at dt 1/60), from the release on, before any bounce.
/// ExactBallistic and Rk4 fly exactly and start at the vertex.
double launch_apex(Real h, Real dt, const WorldDef& def) {
  if (def.integrator != Integrator::SemiImplicitEuler) return double(h);
  const double substep = double(dt) / def.substeps;
  return double(h) + double(kGravity) * substep * substep / 8;
}

/// physics/README.md: "an e = 1 ball dropped from 10 m keeps its height to 3·10⁻⁵ over 20
/// bounces at dt 1/60".
constexpr double kElasticHeightTolerance = 3e-5;  ///< relative to h

class ElasticBounceTest
    : public ::testing::TestWithParam<std::tuple<Integrator, PositionCorrection>> {
 protected:
  static constexpr Real kHeight = 10;  ///< m
  static constexpr int kBounces = 20;
  static WorldDef def() {
    WorldDef d = awake_def();
    d.integrator = std::get<0>(GetParam());
    d.position_correction = std::get<1>(GetParam());
    return d;
  }
};

TEST_P(ElasticBounceTest, KeepsItsHeightToThreeE5OverTwentyBounces) {
  // Measured, every correction: within 3.3·10⁻⁷·h of the launch apex for semi-implicit Euler
  // and 1.3·10⁻⁸·h for the others in float, 7·10⁻¹⁶·h in double. Measured from h itself,
  // semi-implicit Euler is 3.44·10⁻⁵·h high: all of it the launch offset g·dt²/8, none of it
  // lost or gained in a bounce (see NoBounceChangesTheApex).
  const std::vector<double> apexes = elastic_apexes(kHeight, kDt60, def(), kBounces);
  ASSERT_EQ(apexes.size(), std::size_t(kBounces));
  const double apex = launch_apex(kHeight, kDt60, def());
  for (std::size_t k = 0; k < apexes.size(); ++k) {
    EXPECT_NEAR(apexes[k], apex, kElasticHeightTolerance * double(kHeight))
        << "bounce " << k + 1 << " (launch apex " << apex << " m)";
  }
}

TEST_P(ElasticBounceTest, NoBounceChangesTheApex) {
  // Restitution keeps ½·w² + g·y across the impact exactly (apply_restitution), so bounce k's
  // apex equals bounce 1's up to rounding. Measured: identical to the last bit in float,
  // 7·10⁻¹⁶·h apart in double; the bound is a few float ulps of 10 m.
  const std::vector<double> apexes = elastic_apexes(kHeight, kDt60, def(), kBounces);
  ASSERT_EQ(apexes.size(), std::size_t(kBounces));
  for (std::size_t k = 1; k < apexes.size(); ++k)
    EXPECT_NEAR(apexes[k], apexes[0], 1e-6 * double(kHeight)) << "bounce " << k + 1;
}

INSTANTIATE_TEST_SUITE_P(IntegratorsAndCorrections, ElasticBounceTest,
                         ::testing::Combine(::testing::Values(Integrator::SemiImplicitEuler,
                                                              Integrator::ExactBallistic,
                                                              Integrator::Rk4),
                                            ::testing::Values(PositionCorrection::Baumgarte,
                                                              PositionCorrection::SplitImpulse,
                                                              PositionCorrection::SoftStep)),
                         [](const auto& info) {
                           return cat(integrator_name(std::get<0>(info.param)), "_",
                                      correction_name(std::get<1>(info.param)));
                         });

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
}  // namespace ricochet::physics::test::bounce_test
