#pragma once
/// The world's force fields (springs and attractors), stored by slot with generation counters,
/// and the force they exert on one body at a given position and velocity.

#include <cstdint>
#include <vector>

#include "ricochet/physics/body.h"
#include "ricochet/physics/force_field.h"
#include "slot_pool.h"

namespace ricochet::physics {

enum class ForceKind : std::uint8_t { Spring, Attractor };

struct ForceField {
  ForceKind kind = ForceKind::Spring;
  std::uint32_t body = 0;     ///< spring: body slot
  Vec3 point = Vec3::Zero();  ///< m: spring anchor or attractor centre
  Real stiffness = 0;         ///< spring N/m, or attractor strength m³/s²
  Real rest_length = 0;       ///< spring, m
  Real damping = 0;           ///< spring, N·s/m
  Real min_distance = 0;      ///< attractor, m
  std::uint32_t mask = 0;     ///< attractor layers
};

class ForceFields {
 public:
  static constexpr std::uint32_t kMaxFields = 1u << 16;

  std::uint32_t add(const ForceField& field);
  void remove(std::uint32_t slot);
  /// Removes every spring attached to body slot.
  void remove_springs_of(std::uint32_t body);
  bool valid(ForceId id) const { return slots_.valid(id); }
  ForceId id_of(std::uint32_t slot) const { return slots_.id_of<ForceTag>(slot); }
  bool alive(std::uint32_t slot) const { return slots_.alive(slot); }
  bool empty() const { return slots_.alive_count == 0; }
  std::uint32_t count() const { return slots_.alive_count; }
  const SlotPool& slots() const { return slots_; }
  const std::vector<ForceField>& fields() const { return fields_; }
  /// Replaces everything (restore_state); already validated.
  void assign(SlotPool slots, std::vector<ForceField> fields);

  /// Whether any field pulls on body slot (with that collision layer).
  bool acts_on(std::uint32_t body, std::uint32_t layer) const;

  /// N on body slot (layer, 1/kg) at position x (m) moving at v (m/s).
  Vec3 force_on(std::uint32_t body, std::uint32_t layer, Real inverse_mass, const Vec3& x,
                const Vec3& v) const;

 private:
  void rebuild_index();

  SlotPool slots_;
  std::vector<ForceField> fields_;         ///< per slot
  std::vector<std::uint32_t> attractors_;  ///< slots of live attractors, ascending
  /// Live springs sorted by (body, slot): the springs of one body are a contiguous run.
  std::vector<std::uint32_t> springs_;
};

}  // namespace ricochet::physics
