#pragma once
/// Scalar, vector and handle types of the physics module, and its Result/Status error carriers.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <utility>
#include <variant>

namespace ricochet::physics {

#if defined(RICOCHET_DOUBLE)
using Real = double;
#else
using Real = float;
#endif

using Vec3 = Eigen::Matrix<Real, 3, 1>;
using Quat = Eigen::Quaternion<Real>;
using Mat3 = Eigen::Matrix<Real, 3, 3>;

/// A small id with a generation counter, as Box2D's b2BodyId: when the object is destroyed its
/// slot's generation moves on, so a stale handle is reported as InvalidHandle instead of
/// touching whatever reuses the slot. The tag keeps body, shape, projectile and force ids apart.
template <class Tag>
struct Handle {
  std::uint32_t index = 0;       ///< slot
  std::uint32_t generation = 0;  ///< 0 means null
  bool is_null() const { return generation == 0; }
  friend bool operator==(Handle, Handle) = default;
};

/// A dynamic or kinematic body.
using BodyId = Handle<struct BodyTag>;
/// A static shape (plane, box or triangle mesh).
using ShapeId = Handle<struct ShapeTag>;
/// A swept projectile (projectile.h).
using ProjectileId = Handle<struct ProjectileTag>;
/// A force field: a spring or an attractor (force_field.h).
using ForceId = Handle<struct ForceTag>;

enum class ErrorCode : std::uint8_t {
  InvalidArgument,   ///< a definition or parameter is out of range or not finite
  InvalidHandle,     ///< null, stale or out-of-range BodyId / ShapeId
  CapacityExceeded,  ///< more bodies or shapes than the world allows
  CorruptState,      ///< save-state bytes that fail validation
};

/// What went wrong, written for the person who must fix it: what was expected and what came.
struct Error {
  ErrorCode code;
  std::string message;
};

/// A value or an Error. Never throws; check ok() before value().
template <class T>
class [[nodiscard]] Result {
 public:
  Result(T value) : data_(std::move(value)) {}
  Result(Error error) : data_(std::move(error)) {}
  bool ok() const { return data_.index() == 0; }
  explicit operator bool() const { return ok(); }
  T& value() & { return std::get<0>(data_); }
  const T& value() const& { return std::get<0>(data_); }
  /// Moves the value out of a temporary: `World w = World::create(def).value();`
  T&& value() && { return std::get<0>(std::move(data_)); }
  const Error& error() const { return std::get<1>(data_); }

 private:
  std::variant<T, Error> data_;
};

/// Success or an Error.
class [[nodiscard]] Status {
 public:
  Status() = default;
  Status(Error error) : error_(std::move(error)), ok_(false) {}
  bool ok() const { return ok_; }
  explicit operator bool() const { return ok_; }
  const Error& error() const { return error_; }

 private:
  Error error_{ErrorCode::InvalidArgument, {}};
  bool ok_ = true;
};

}  // namespace ricochet::physics
