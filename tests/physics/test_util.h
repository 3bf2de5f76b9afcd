#pragma once
/// Shared helpers for the physics tests: a world with a floor in two lines, spheres, stepping with
/// error reporting, error-code matchers, energy bookkeeping and finiteness checks.
///
/// Helpers that must hand back a value (a World, a BodyId) cannot use ASSERT_*; they throw
/// std::runtime_error with the library's message instead, which GoogleTest reports as a failure of
/// the test that called them.

#include <gtest/gtest.h>

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "ricochet/physics/world.h"

namespace ricochet::physics {

// GoogleTest printers (found by ADL) so failures show names instead of byte dumps.
inline const char* error_code_name(ErrorCode code) {
  switch (code) {
    case ErrorCode::InvalidArgument:
      return "InvalidArgument";
    case ErrorCode::InvalidHandle:
      return "InvalidHandle";
    case ErrorCode::CapacityExceeded:
      return "CapacityExceeded";
    case ErrorCode::CorruptState:
      return "CorruptState";
  }
  return "ErrorCode(?)";
}
inline void PrintTo(ErrorCode code, std::ostream* os) {
  *os << error_code_name(code);
}
inline void PrintTo(BodyId id, std::ostream* os) {
  *os << "BodyId{" << id.index << ", gen " << id.generation << "}";
}
inline void PrintTo(ShapeId id, std::ostream* os) {
  *os << "ShapeId{" << id.index << ", gen " << id.generation << "}";
}

namespace test {

inline constexpr bool kDoublePrecision = std::is_same_v<Real, double>;
inline constexpr Real kEps = std::numeric_limits<Real>::epsilon();
inline constexpr Real kNaN = std::numeric_limits<Real>::quiet_NaN();
inline constexpr Real kInf = std::numeric_limits<Real>::infinity();
inline constexpr Real kDt60 = Real(1) / Real(60);
inline constexpr Real kGravity = Real(9.81);  ///< magnitude of the default WorldDef gravity

/// Concatenates anything streamable (avoids `"literal" + std::to_string(...)`, which trips
/// GCC 12's -Wrestrict false positive at -O3).
template <class... Parts>
std::string cat(const Parts&... parts) {
  std::ostringstream out;
  (out << ... << parts);
  return out.str();
}

// ---------------------------------------------------------------------------------------------
// Results and errors

inline std::string describe(const Error& error) {
  return cat(error_code_name(error.code), ": ", error.message);
}

/// The value of an ok Result; throws (failing the calling test) with the library's message
/// otherwise.
template <class T>
T unwrap(Result<T> result, std::string_view what) {
  if (!result.ok()) throw std::runtime_error(cat(what, " failed: ", describe(result.error())));
  return std::move(result.value());
}

inline void check(const Status& status, std::string_view what) {
  if (!status.ok()) throw std::runtime_error(cat(what, " failed: ", describe(status.error())));
}

/// EXPECT_TRUE(fails_with(world.step(0), ErrorCode::InvalidArgument)): the call failed, with that
/// code and a message a person can act on.
template <class R>
::testing::AssertionResult fails_with(const R& result, ErrorCode code) {
  if (result.ok()) {
    return ::testing::AssertionFailure() << "succeeded, expected " << error_code_name(code);
  }
  if (result.error().code != code) {
    return ::testing::AssertionFailure()
           << "failed with " << error_code_name(result.error().code) << ", expected "
           << error_code_name(code) << " (message: \"" << result.error().message << "\")";
  }
  if (result.error().message.empty()) {
    return ::testing::AssertionFailure()
           << "failed with " << error_code_name(code) << " but the message is empty";
  }
  return ::testing::AssertionSuccess();
}

#define RICOCHET_ASSERT_OK(expr)                                                             \
  do {                                                                                       \
    const auto& ricochet_result_ = (expr);                                                   \
    ASSERT_TRUE(ricochet_result_.ok()) << #expr << ": " << ricochet_result_.error().message; \
  } while (false)

#define RICOCHET_EXPECT_OK(expr)                                                             \
  do {                                                                                       \
    const auto& ricochet_result_ = (expr);                                                   \
    EXPECT_TRUE(ricochet_result_.ok()) << #expr << ": " << ricochet_result_.error().message; \
  } while (false)

// ---------------------------------------------------------------------------------------------
// Worlds, statics and bodies

/// A WorldDef with sleeping off, so a test about resting or motion is not passed by a body that
/// simply fell asleep.
inline WorldDef awake_def(const Vec3& gravity = Vec3(0, -kGravity, 0)) {
  WorldDef def;
  def.gravity = gravity;
  def.enable_sleep = false;
  return def;
}

/// Zero gravity, sleeping off: for collisions and queries where only the tested motion matters.
inline WorldDef space_def() {
  return awake_def(Vec3::Zero());
}

inline World make_world(const WorldDef& def = awake_def()) {
  return unwrap(World::create(def), "World::create");
}

inline Material material(Real restitution, Real friction, Real rolling_resistance = 0) {
  Material m;
  m.restitution = restitution;
  m.friction = friction;
  m.rolling_resistance = rolling_resistance;
  return m;
}

inline ShapeId add_plane(World& world, const Vec3& normal, Real offset, const Material& m = {}) {
  PlaneDef def;
  def.normal = normal;
  def.offset = offset;
  def.material = m;
  return unwrap(world.add_plane(def), "add_plane");
}

/// The plane y = height, solid below.
inline ShapeId add_floor(World& world, Real height = 0, const Material& m = {}) {
  return add_plane(world, Vec3::UnitY(), height, m);
}

/// Six planes enclosing |x| <= half_width, |z| <= half_width, 0 <= y <= height.
inline std::vector<ShapeId> add_closed_box(World& world, Real half_width, Real height,
                                           const Material& m = {}) {
  return {
      add_plane(world, Vec3::UnitY(), 0, m),
      add_plane(world, -Vec3::UnitY(), -height, m),
      add_plane(world, Vec3::UnitX(), -half_width, m),
      add_plane(world, -Vec3::UnitX(), -half_width, m),
      add_plane(world, Vec3::UnitZ(), -half_width, m),
      add_plane(world, -Vec3::UnitZ(), -half_width, m),
  };
}

inline ShapeId add_box(World& world, const Vec3& center, const Vec3& half_extents,
                       const Quat& orientation = Quat::Identity(), const Material& m = {}) {
  BoxDef def;
  def.center = center;
  def.half_extents = half_extents;
  def.orientation = orientation;
  def.material = m;
  return unwrap(world.add_box(def), "add_box");
}

inline ShapeId add_mesh(World& world, std::vector<Vec3> vertices,
                        std::vector<std::uint32_t> indices, const Material& m = {}) {
  MeshDef def;
  def.vertices = std::move(vertices);
  def.indices = std::move(indices);
  def.material = m;
  return unwrap(world.add_mesh(def), "add_mesh");
}

inline BodyDef sphere_def(const Vec3& position, Real radius = Real(0.5), Real mass = 1,
                          const Material& m = {}) {
  BodyDef def;
  def.position = position;
  def.radius = radius;
  def.mass = mass;
  def.material = m;
  return def;
}

inline BodyId add_body(World& world, const BodyDef& def) {
  return unwrap(world.create_body(def), "create_body");
}

inline BodyId add_sphere(World& world, const Vec3& position, Real radius = Real(0.5), Real mass = 1,
                         const Material& m = {}) {
  return add_body(world, sphere_def(position, radius, mass, m));
}

inline BodyState state_of(const World& world, BodyId id) {
  return unwrap(world.body_state(id), "body_state");
}

/// Steps n times; reports the first failing step with its message.
inline ::testing::AssertionResult run(World& world, int steps, Real dt = kDt60) {
  for (int i = 0; i < steps; ++i) {
    const Status status = world.step(dt);
    if (!status.ok()) {
      return ::testing::AssertionFailure()
             << "step " << i << " of " << steps << " failed: " << describe(status.error());
    }
  }
  return ::testing::AssertionSuccess();
}

/// Steps n times inside a helper that returns a value; throws on a failing step.
inline void run_or_throw(World& world, int steps, Real dt = kDt60) {
  const ::testing::AssertionResult result = run(world, steps, dt);
  if (!result) throw std::runtime_error(result.message());
}

inline int steps_for(double seconds, Real dt) {
  return static_cast<int>(std::lround(seconds / static_cast<double>(dt)));
}

// ---------------------------------------------------------------------------------------------
// State inspection

inline bool is_finite(const BodyState& s) {
  return s.position.allFinite() && s.orientation.coeffs().allFinite() &&
         s.linear_velocity.allFinite() && s.angular_velocity.allFinite() && s.force.allFinite() &&
         s.torque.allFinite() && std::isfinite(s.radius) && std::isfinite(s.inverse_mass) &&
         s.inverse_inertia_world.allFinite();
}

inline Eigen::Vector3d to_d(const Vec3& v) {
  return v.cast<double>();
}

/// EXPECT_TRUE(bounded(s, centre, reach_m, max_speed)): the state is finite, its position within
/// reach_m metres of centre and its speed at most max_speed m/s (no explosion); says which bound
/// broke otherwise.
inline ::testing::AssertionResult bounded(const BodyState& s, const Vec3& centre, double reach_m,
                                          double max_speed) {
  if (!is_finite(s)) return ::testing::AssertionFailure() << "state is not finite";
  const double distance = (to_d(s.position) - to_d(centre)).norm();
  if (distance > reach_m) {
    return ::testing::AssertionFailure() << "position (" << s.position.transpose() << ") is "
                                         << distance << " m from the centre, limit " << reach_m;
  }
  const double speed = to_d(s.linear_velocity).norm();
  if (speed > max_speed) {
    return ::testing::AssertionFailure() << "speed " << speed << " m/s, limit " << max_speed;
  }
  return ::testing::AssertionSuccess();
}

/// Kinetic energy, linear plus rotational, in double. A body with zero inverse inertia (locked
/// rotation) has no rotational term; a kinematic body (inverse mass 0) has none at all.
inline double kinetic_energy(const BodyState& s) {
  if (s.inverse_mass <= 0) return 0;
  const double mass = 1.0 / static_cast<double>(s.inverse_mass);
  double e = 0.5 * mass * to_d(s.linear_velocity).squaredNorm();
  const Eigen::Matrix3d inv_inertia = s.inverse_inertia_world.cast<double>();
  if (std::abs(inv_inertia.determinant()) > 0) {
    const Eigen::Vector3d w = to_d(s.angular_velocity);
    e += 0.5 * w.dot(inv_inertia.inverse() * w);
  }
  return e;
}

/// Gravitational potential energy -m·g·x (zero at the origin).
inline double potential_energy(const BodyState& s, const Vec3& gravity) {
  if (s.inverse_mass <= 0) return 0;
  const double mass = 1.0 / static_cast<double>(s.inverse_mass);
  return -mass * to_d(gravity).dot(to_d(s.position));
}

/// EXPECT_TRUE(near(a, b, tol)): |a − b| <= tol, printing both vectors otherwise.
inline ::testing::AssertionResult near(const Vec3& a, const Vec3& b, double tol) {
  const double d = (to_d(a) - to_d(b)).norm();
  if (d <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "(" << a.transpose() << ") is " << d << " from ("
                                       << b.transpose() << "), tolerance " << tol;
}

inline std::string hex(std::uint64_t value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "0x%016" PRIx64, value);
  return buffer;
}

/// Bitwise equality of two body states (what determinism and rollback promise).
inline ::testing::AssertionResult same_state(const BodyState& a, const BodyState& b) {
  auto eq = [](const auto& x, const auto& y) { return (x.array() == y.array()).all(); };
  if (!eq(a.position, b.position)) {
    return ::testing::AssertionFailure()
           << "position " << a.position.transpose() << " vs " << b.position.transpose();
  }
  if (!eq(a.orientation.coeffs(), b.orientation.coeffs())) {
    return ::testing::AssertionFailure() << "orientation differs";
  }
  if (!eq(a.linear_velocity, b.linear_velocity)) {
    return ::testing::AssertionFailure() << "linear velocity " << a.linear_velocity.transpose()
                                         << " vs " << b.linear_velocity.transpose();
  }
  if (!eq(a.angular_velocity, b.angular_velocity)) {
    return ::testing::AssertionFailure() << "angular velocity differs";
  }
  if (a.sleeping != b.sleeping || a.frozen != b.frozen) {
    return ::testing::AssertionFailure() << "sleeping/frozen flags differ";
  }
  return ::testing::AssertionSuccess();
}

/// Everything observable about a world that a rejected call must leave alone.
struct WorldSnapshot {
  std::uint64_t hash = 0;
  std::uint64_t steps = 0;
  std::uint32_t bodies = 0;
  std::uint32_t shapes = 0;
  std::vector<std::uint8_t> image;
};

inline WorldSnapshot snapshot(const World& world) {
  return {world.state_hash(), world.step_count(), world.body_count(), world.shape_count(),
          world.save_state()};
}

/// EXPECT_TRUE(unchanged(world, before)).
inline ::testing::AssertionResult unchanged(const World& world, const WorldSnapshot& before) {
  const WorldSnapshot now = snapshot(world);
  if (now.hash != before.hash) return ::testing::AssertionFailure() << "state hash changed";
  if (now.steps != before.steps) return ::testing::AssertionFailure() << "step count changed";
  if (now.bodies != before.bodies) return ::testing::AssertionFailure() << "body count changed";
  if (now.shapes != before.shapes) return ::testing::AssertionFailure() << "shape count changed";
  if (now.image != before.image) return ::testing::AssertionFailure() << "saved image changed";
  return ::testing::AssertionSuccess();
}

/// Small deterministic generator (no dependence on the standard library's distributions, whose
/// output differs between implementations).
class Lcg {
 public:
  explicit Lcg(std::uint64_t seed)
      : state_(seed * 6364136223846793005ull + 1442695040888963407ull) {}
  /// Uniform in [0, 1).
  double next() {
    state_ = state_ * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state_ >> 11) * (1.0 / 9007199254740992.0);
  }
  Real uniform(double lo, double hi) { return static_cast<Real>(lo + (hi - lo) * next()); }
  std::uint8_t byte() { return static_cast<std::uint8_t>(next() * 256.0); }

 private:
  std::uint64_t state_;
};

inline const char* integrator_name(Integrator i) {
  switch (i) {
    case Integrator::ExplicitEuler:
      return "ExplicitEuler";
    case Integrator::SemiImplicitEuler:
      return "SemiImplicitEuler";
    case Integrator::ExactBallistic:
      return "ExactBallistic";
    case Integrator::Rk4:
      return "Rk4";
  }
  return "Unknown";
}

inline const char* correction_name(PositionCorrection c) {
  switch (c) {
    case PositionCorrection::Baumgarte:
      return "Baumgarte";
    case PositionCorrection::SplitImpulse:
      return "SplitImpulse";
    case PositionCorrection::SoftStep:
      return "SoftStep";
  }
  return "Unknown";
}

/// def with the given position correction; SoftStep also gets the 4 substeps it is meant to run
/// with (world_def.h: "SoftStep wants substeps >= 4").
inline WorldDef with_correction(WorldDef def, PositionCorrection correction) {
  def.position_correction = correction;
  if (correction == PositionCorrection::SoftStep && def.substeps < 4) def.substeps = 4;
  return def;
}

inline constexpr PositionCorrection kAllCorrections[] = {
    PositionCorrection::Baumgarte, PositionCorrection::SplitImpulse, PositionCorrection::SoftStep};

}  // namespace test
}  // namespace ricochet::physics
