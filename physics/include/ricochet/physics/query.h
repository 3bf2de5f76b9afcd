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
  ContactTarget target;
  Vec3 point;     ///< m, where the ray (or the cast sphere's surface) touches
  Vec3 normal;    ///< unit, pointing back towards the caster
  Real fraction;  ///< 0..1 along the cast
  Real distance;  ///< m along the cast
};

}  // namespace ricochet::physics
