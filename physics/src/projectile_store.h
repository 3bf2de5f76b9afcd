#pragma once
/// Projectiles in structure-of-arrays slots with generations, like BodyStore.

#include <cstdint>
#include <cstring>
#include <vector>

#include "ricochet/physics/projectile.h"
#include "slot_pool.h"

namespace ricochet::physics {

struct ProjectileStore {
  SlotPool slots;
  std::vector<Vec3> position;  ///< m
  std::vector<Vec3> velocity;  ///< m/s
  std::vector<Real> radius;    ///< m
  std::vector<Real> gravity_scale;
  std::vector<Filter> filter;
  std::vector<BodyId> ignore;
  std::vector<std::uint64_t> user_data;

  std::uint32_t slot_count() const { return slots.slot_count(); }
  bool alive(std::uint32_t slot) const { return slots.alive(slot); }
  bool valid(ProjectileId id) const { return slots.valid(id); }
  ProjectileId id_of(std::uint32_t slot) const { return slots.id_of<ProjectileTag>(slot); }

  std::uint32_t create(const ProjectileDef& def) {
    const std::uint32_t slot = slots.acquire();
    resize(slots.slot_count());
    position[slot] = def.position;
    velocity[slot] = def.velocity;
    radius[slot] = def.radius;
    gravity_scale[slot] = def.gravity_scale;
    filter[slot] = def.filter;
    ignore[slot] = def.ignore;
    user_data[slot] = def.user_data;
    return slot;
  }

  void destroy(std::uint32_t slot) { slots.release(slot); }

  /// Whether slots a and b have the same radius, gravity scale and filter (bit for bit).
  bool same_shape(std::uint32_t a, std::uint32_t b) const {
    return std::memcmp(&radius[a], &radius[b], sizeof(Real)) == 0 &&
           std::memcmp(&gravity_scale[a], &gravity_scale[b], sizeof(Real)) == 0 &&
           filter[a].layer == filter[b].layer && filter[a].mask == filter[b].mask;
  }
  void copy_shape(std::uint32_t to, std::uint32_t from) {
    radius[to] = radius[from];
    gravity_scale[to] = gravity_scale[from];
    filter[to] = filter[from];
  }

  /// Grows (or shrinks) every per-slot array but the pool's to `count` slots.
  void resize(std::uint32_t count) {
    position.resize(count, Vec3::Zero());
    velocity.resize(count, Vec3::Zero());
    radius.resize(count, 0);
    gravity_scale.resize(count, 0);
    filter.resize(count);
    ignore.resize(count);
    user_data.resize(count, 0);
  }
};

}  // namespace ricochet::physics
