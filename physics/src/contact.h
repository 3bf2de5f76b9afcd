#pragma once
/// Contact constraint data shared by the narrowphase, the solver and event reporting.

#include <cstdint>
#include <vector>

#include "ricochet/physics/types.h"

namespace ricochet::physics {

/// One contact point between a body (a) and another body or a static primitive (b).
/// Spheres touch at a single point on the line between centres, so the lever arms are parallel to
/// the normal: rA = ra·n, rB = -rb·n. The normal impulse then causes no torque.
struct Contact {
  // Geometry and material, from the narrowphase.
  std::uint32_t a = 0;          ///< body slot
  std::uint32_t b = 0;          ///< body slot for body pairs, shape slot for static contacts
  Vec3 normal = Vec3::UnitY();  ///< unit, from a towards b
  Real separation = 0;          ///< m at step start; negative when penetrating
  Real ra = 0, rb = 0;          ///< m, lever lengths along the normal
  Real friction = 0;
  Real rolling = 0;                      ///< m: max rolling torque per unit normal impulse
  Real normal_impulse = 0;               ///< N·s, accumulated per substep (warm started)
  Vec3 friction_impulse = Vec3::Zero();  ///< N·s, in the tangent plane
  Vec3 rolling_impulse = Vec3::Zero();   ///< N·m·s
  // Results, for warm starting and events.
  Real restitution = 0;
  Real relative_velocity = 0;     ///< m/s along the normal at prepare (negative = approaching)
  Real max_normal_impulse = 0;    ///< N·s, largest per-substep normal impulse this step
  Real total_normal_impulse = 0;  ///< N·s over the whole step
  std::uint64_t key = 0;          ///< identity across steps for warm starting and events
  Vec3 point = Vec3::Zero();      ///< m, midway between the surfaces
  bool previously_touching = false;
  bool touching = false;
};

/// Contact keys: body pairs use (a << 32 | b) with a < b; static contacts set the top bit and pack
/// body (22 bits), shape (20 bits) and triangle (21 bits).
inline std::uint64_t pair_key(std::uint32_t a, std::uint32_t b) {
  return (static_cast<std::uint64_t>(a) << 32) | b;
}
inline std::uint64_t static_key(std::uint32_t body, std::uint32_t shape, std::uint32_t triangle) {
  return (1ull << 63) | (static_cast<std::uint64_t>(body) << 41) |
         (static_cast<std::uint64_t>(shape) << 21) | triangle;
}
constexpr std::uint32_t kMaxBodySlots = 1u << 22;
constexpr std::uint32_t kMaxProjectileSlots = 1u << 22;
constexpr std::uint32_t kMaxShapeSlots = 1u << 20;
constexpr std::uint32_t kMaxMeshTriangles = 1u << 21;

/// Open-addressing map from contact key to index in last step's contact list.
class ContactCache {
 public:
  void build(const std::vector<Contact>& pairs, const std::vector<Contact>& statics);
  /// Index into pairs (< pair_count) or statics (>= pair_count, offset), or -1.
  std::int64_t find(std::uint64_t key) const;

 private:
  static constexpr std::uint64_t kEmpty = ~0ull;
  std::vector<std::uint64_t> keys_;
  /// Fibonacci hashing: the top bits of key·2^64/φ.
  std::uint64_t slot_of(std::uint64_t key) const { return (key * 0x9E3779B97F4A7C15ull) >> shift_; }
  std::vector<std::uint32_t> values_;
  std::uint64_t mask_ = 0;
  unsigned shift_ = 60;
};

}  // namespace ricochet::physics
