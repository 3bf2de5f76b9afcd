#pragma once
/// Projectiles in structure-of-arrays slots with generations, like BodyStore.

#include <cstdint>
#include <vector>

#include "ricochet/physics/projectile.h"

namespace ricochet::physics {

struct ProjectileStore {
  std::vector<std::uint32_t> generation;
  std::vector<std::uint8_t> alive;
  std::vector<Vec3> position;  ///< m
  std::vector<Vec3> velocity;  ///< m/s
  std::vector<Real> radius;    ///< m
  std::vector<Real> gravity_scale;
  std::vector<Filter> filter;
  std::vector<BodyId> ignore;
  std::vector<std::uint64_t> user_data;
  std::vector<std::uint32_t> free_slots;
  std::uint32_t alive_count = 0;

  std::uint32_t slot_count() const { return static_cast<std::uint32_t>(generation.size()); }
  bool valid(ProjectileId id) const {
    return id.index < slot_count() && alive[id.index] && generation[id.index] == id.generation;
  }
  ProjectileId id_of(std::uint32_t slot) const { return {slot, generation[slot]}; }

  std::uint32_t create(const ProjectileDef& def) {
    std::uint32_t slot;
    if (!free_slots.empty()) {
      slot = free_slots.back();
      free_slots.pop_back();
    } else {
      slot = slot_count();
      resize(slot + 1);
    }
    if (++generation[slot] == 0) generation[slot] = 1;  // 0 is the null handle
    alive[slot] = 1;
    position[slot] = def.position;
    velocity[slot] = def.velocity;
    radius[slot] = def.radius;
    gravity_scale[slot] = def.gravity_scale;
    filter[slot] = def.filter;
    ignore[slot] = def.ignore;
    user_data[slot] = def.user_data;
    ++alive_count;
    return slot;
  }

  void destroy(std::uint32_t slot) {
    alive[slot] = 0;
    free_slots.push_back(slot);
    --alive_count;
  }

  void resize(std::uint32_t slots) {
    generation.resize(slots, 0);
    alive.resize(slots, 0);
    position.resize(slots, Vec3::Zero());
    velocity.resize(slots, Vec3::Zero());
    radius.resize(slots, 0);
    gravity_scale.resize(slots, 0);
    filter.resize(slots);
    ignore.resize(slots);
    user_data.resize(slots, 0);
  }
};

}  // namespace ricochet::physics
