#pragma once
/// Ray casts, sphere casts and overlap queries against bodies and static shapes.

#include <cstdint>

#include "ricochet/physics/events.h"

namespace ricochet::physics {

struct QueryFilter {
  std::uint32_t mask = 0xFFFFFFFFu;  ///< objects whose layer has no bit in mask are skipped
  bool bodies = true;                ///< include dynamic and kinematic bodies
  bool statics = true;               ///< include static shapes
  bool sensors = false;              ///< include sensor bodies
  BodyId ignore;                     ///< a body to skip, e.g. the shooter
};

struct RayHit {
  ContactTarget target;  ///< what was hit, with the body's user_data
  Vec3 point;            ///< m, where the ray (or the cast sphere's surface) touches
  Vec3 normal;           ///< unit, pointing back towards the caster
  Real fraction;         ///< 0..1 along the cast
  Real distance;         ///< m along the cast
};

/// A sphere standing in for a body at another time, for lag compensation: a player where the
/// shooter's client saw it. Casts against proxies read and change nothing in the world.
struct SphereProxy {
  Vec3 center;      ///< m
  Real radius = 0;  ///< m, > 0 (a proxy with a non-finite or non-positive field is skipped)
  BodyId body;      ///< reported in RayHit::target
  std::uint64_t user_data = 0;  ///< reported in RayHit::target
};

}  // namespace ricochet::physics
