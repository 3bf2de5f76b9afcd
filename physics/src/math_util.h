#pragma once
/// Small numeric helpers shared by the physics sources.

#include <cmath>
#include <cstdint>
#include <limits>

#include "ricochet/physics/types.h"

namespace ricochet::physics {

inline bool is_finite(Real x) {
  return std::isfinite(x);
}
inline bool is_finite(const Vec3& v) {
  return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
}
inline bool is_finite(const Quat& q) {
  return std::isfinite(q.w()) && std::isfinite(q.x()) && std::isfinite(q.y()) &&
         std::isfinite(q.z());
}

/// Axis-aligned bounding box.
struct Aabb {
  Vec3 min = Vec3::Constant(std::numeric_limits<Real>::max());
  Vec3 max = Vec3::Constant(-std::numeric_limits<Real>::max());

  static Aabb around_sphere(const Vec3& center, Real radius) {
    return {center - Vec3::Constant(radius), center + Vec3::Constant(radius)};
  }
  void grow(const Vec3& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  void grow(const Aabb& b) {
    min = min.cwiseMin(b.min);
    max = max.cwiseMax(b.max);
  }
  bool overlaps(const Aabb& b) const {
    return min.x() <= b.max.x() && max.x() >= b.min.x() && min.y() <= b.max.y() &&
           max.y() >= b.min.y() && min.z() <= b.max.z() && max.z() >= b.min.z();
  }
  Vec3 center() const { return (min + max) * Real(0.5); }
};

/// 64-bit FNV-1a, used for state hashes.
class Fnv1a {
 public:
  void add(const void* data, std::size_t size) {
    const auto* bytes = static_cast<const std::uint8_t*>(data);
    for (std::size_t i = 0; i < size; ++i) {
      hash_ ^= bytes[i];
      hash_ *= 1099511628211ull;
    }
  }
  template <class T>
  void add_value(const T& value) {
    add(&value, sizeof value);
  }
  std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 14695981039346656037ull;
};

/// A unit vector perpendicular-ish to nothing in particular, used when a normal is undefined
/// (two centres coincide). Fixed so the result stays deterministic.
inline Vec3 fallback_normal() {
  return Vec3::UnitY();
}

}  // namespace ricochet::physics
