#pragma once
/// Body storage: structure of arrays indexed by slot (BodyId::index), with generation counters.
/// Hot solver data (velocities and inverse masses) lives in `motion`, contiguous per body.

#include <cstdint>
#include <vector>

#include "ricochet/physics/body.h"
#include "slot_pool.h"

namespace ricochet::physics {

/// What the contact solver touches for every contact: 32 bytes per body in float.
struct Motion {
  Vec3 linear_velocity = Vec3::Zero();   ///< m/s
  Real inverse_mass = 0;                 ///< 1/kg
  Vec3 angular_velocity = Vec3::Zero();  ///< rad/s
  Real inverse_inertia = 0;  ///< 1/(kg·m²); spheres are isotropic so one scalar suffices
};

/// Per-body flags; a dead slot's flags are 0 (whether a slot is alive is its generation's, in
/// SlotPool).
enum BodyFlag : std::uint16_t {
  kFlagKinematic = 1 << 0,
  kFlagLockRotation = 1 << 1,
  kFlagFast = 1 << 2,
  kFlagSensor = 1 << 3,
  kFlagAllowSleep = 1 << 4,
  kFlagSleeping = 1 << 5,
  kFlagFrozen = 1 << 6,
  /// The last move was exact for constant acceleration (ExactBallistic or Rk4 free flight), so
  /// the stored velocity is the true end-of-step one, not the semi-implicit step mean.
  kFlagExactVelocity = 1 << 7,
};

struct BodyStore {
  SlotPool slots;
  std::vector<std::uint16_t> flags;
  std::vector<Vec3> position;
  std::vector<Quat> orientation;
  std::vector<Motion> motion;
  std::vector<Vec3> force;
  std::vector<Vec3> torque;
  std::vector<Real> radius;
  std::vector<Real> mass_inverse_original;     ///< inverse mass before any freeze
  std::vector<Real> inertia_inverse_original;  ///< inverse inertia before any freeze
  std::vector<Real> gravity_scale;
  std::vector<Material> material;
  std::vector<Filter> filter;
  std::vector<Real> sleep_time;  ///< s the body has been slow
  std::vector<std::uint64_t> user_data;

  std::uint32_t slot_count() const { return slots.slot_count(); }
  bool alive(std::uint32_t slot) const { return slots.alive(slot); }
  bool has(std::uint32_t slot, std::uint16_t flag_mask) const {
    return (flags[slot] & flag_mask) != 0;
  }
  bool valid(BodyId id) const { return slots.valid(id); }
  BodyId id_of(std::uint32_t slot) const { return slots.id_of<BodyTag>(slot); }
  /// Dynamic, alive, awake and not frozen: the bodies the solver moves.
  bool simulated(std::uint32_t slot) const {
    return alive(slot) && (flags[slot] & (kFlagKinematic | kFlagSleeping | kFlagFrozen)) == 0;
  }

  /// Takes a slot (reusing the last dead one first) and fills it from a validated definition.
  std::uint32_t create(const BodyDef& def);
  void destroy(std::uint32_t slot);
  BodyState state(std::uint32_t slot) const;
};

}  // namespace ricochet::physics
