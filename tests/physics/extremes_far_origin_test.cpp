// Stability far from the origin: the same small scene (a ball rolling on a floor plane, a ball
// bouncing on it, a three-sphere stack) run at the origin and translated by up to 1e5 m along
// every axis. After 10 s at 60 Hz each body's position relative to the scene's own origin must
// match the origin run.
//
// Positions are stored in Real. In float a coordinate near D carries a rounding step of about
// D·6e-8 m (61 µm at 1 km, 7.8 mm at 100 km), and every step's x += v·dt is rounded to it, so
// the deviation grows with D; in double it stays far below a millimetre everywhere. The largest
// distance at which float keeps 1 mm was found by the scan printed here and is asserted, so a
// change that costs precision is caught.

#include "test_util.h"

namespace ricochet::physics::test::extremes_far_origin_test {
namespace {

constexpr int kSteps = 600;          ///< 10 s at 60 Hz
constexpr double kTolerance = 1e-3;  ///< m

/// The scene's bodies, described relative to its own origin.
std::vector<BodyDef> scene_bodies() {
  std::vector<BodyDef> bodies;
  BodyDef rolling = sphere_def(Vec3(0, Real(0.5), 0), Real(0.5), 1, material(0, Real(0.6)));
  rolling.linear_velocity = Vec3(3, 0, 1);
  bodies.push_back(rolling);
  BodyDef bouncing =
      sphere_def(Vec3(-3, 2, 2), Real(0.3), 2, material(Real(0.6), Real(0.6), Real(0.01)));
  bouncing.linear_velocity = Vec3(Real(-0.5), 0, Real(0.25));
  bodies.push_back(bouncing);
  for (int k = 0; k < 3; ++k) {
    bodies.push_back(sphere_def(Vec3(3, Real(0.4 + 0.8 * k), -3), Real(0.4), 1, material(0, 1)));
  }
  return bodies;
}

/// Runs the scene translated by `offset` for 10 s and returns each body's position minus the
/// offset (in double, so the subtraction itself adds no error).
std::vector<Eigen::Vector3d> run_translated(const Vec3& offset) {
  World world = make_world();
  add_floor(world, offset.y());
  std::vector<BodyId> ids;
  for (BodyDef def : scene_bodies()) {
    def.position += offset;
    ids.push_back(add_body(world, def));
  }
  for (int i = 0; i < kSteps; ++i) {
    run_or_throw(world, 1);
    for (BodyId id : ids) {
      const BodyState s = state_of(world, id);
      // No explosion: finite, within 50 m of the scene (the rolling ball covers ~22 m), no
      // faster than it started (3.2 m/s) or than a fall from 2 m (6.3 m/s).
      const ::testing::AssertionResult sane = bounded(s, offset, 50, 7);
      if (!sane)
        throw std::runtime_error(cat("offset ", offset.x(), ", step ", i, ": ", sane.message()));
    }
  }
  std::vector<Eigen::Vector3d> relative;
  for (BodyId id : ids) relative.push_back(to_d(state_of(world, id).position) - to_d(offset));
  return relative;
}

/// Largest distance between a body's relative position and the same body's in `reference`.
double deviation(const std::vector<Eigen::Vector3d>& run,
                 const std::vector<Eigen::Vector3d>& reference) {
  double worst = 0;
  for (std::size_t k = 0; k < run.size(); ++k)
    worst = std::max(worst, (run[k] - reference[k]).norm());
  return worst;
}

double deviation_at(double distance) {
  static const std::vector<Eigen::Vector3d> reference = run_translated(Vec3::Zero());
  return deviation(run_translated(Vec3::Constant(Real(distance))), reference);
}

/// Largest power-of-two distance up to which every float run of the scan keeps 1 mm, as measured
/// (0.92 mm at 32 m, 1.85 mm at 64 m; 1.6 cm at 1 km). Asserted so a precision regression is
/// caught; raise it when the engine gets more precise.
constexpr double kFloatLimit = 32;

TEST(ExtremeFarOrigin, KeepsOneMillimetreUpToMeasuredLimit) {
  std::printf("\n  far origin (%s), scene offset by (D, D, D): deviation after 10 s\n",
              kDoublePrecision ? "double" : "float");
  std::vector<double> distances;
  for (int power = 0; power <= 17; ++power) distances.push_back(std::ldexp(1.0, power));
  distances.insert(distances.end(), {1e3, 1e4, 1e5});
  std::sort(distances.begin(), distances.end());
  double measured_limit = 0;
  bool all_within = true;
  for (const double distance : distances) {
    const double dev = deviation_at(distance);
    std::printf("  D = %7.0f m   deviation %.3g m\n", distance, dev);
    RecordProperty(cat("deviation_m_at_", distance), cat(dev));
    all_within = all_within && dev < kTolerance;
    if (all_within) measured_limit = distance;
    if (kDoublePrecision || distance <= kFloatLimit) {
      EXPECT_LT(dev, kTolerance) << "D = " << distance << " m";
    }
  }
  std::printf("  largest D up to which every run keeps 1 mm: %.0f m\n", measured_limit);
  std::fflush(stdout);
}

TEST(ExtremeFarOrigin, OneKilometreFromOriginStaysWithinItsDocumentedError) {
  // A documented limit, not a target: in float the deviation at 1 km (1.6 cm measured) is the
  // rounding of x += v·dt to float's 61–122 µm spacing there, accumulated over 600 steps by the two
  // moving balls (offsetting the scene along y alone keeps it within 25 µm). Games farther out
  // than kFloatLimit from the origin that need millimetres should build with RICOCHET_DOUBLE=ON
  // or rebase their origin; double keeps 1 mm here.
  const double bound = kDoublePrecision ? kTolerance : 0.05;
  EXPECT_LT(deviation_at(1e3), bound);
}

// Found by the restore_state fuzzer (UBSan: signed overflow counting the broadphase's cells):
// bodies 10^8 m apart on every axis.
TEST(ExtremeFarOrigin, BodiesFarApartOnEveryAxisStepCleanly) {
  World world = make_world(WorldDef{});
  const BodyId a = add_sphere(world, Vec3(-1e8, -1e8, -1e8));
  const BodyId b = add_sphere(world, Vec3(1e8, 1e8, 1e8));
  ASSERT_TRUE(run(world, 2));
  EXPECT_TRUE(is_finite(state_of(world, a)));
  EXPECT_TRUE(is_finite(state_of(world, b)));
}

}  // namespace
}  // namespace ricochet::physics::test::extremes_far_origin_test
