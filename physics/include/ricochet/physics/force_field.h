#pragma once
/// Position-dependent forces owned by the world: springs to fixed anchors and point attractors.
/// The integrator evaluates them itself (at the start of a substep for the Euler integrators, at
/// every stage for Rk4), which a force applied by game code before the step cannot offer.

#include <cstdint>

#include "ricochet/physics/types.h"

namespace ricochet::physics {

/// A Hooke spring from a dynamic body's centre to a fixed world point, with a dashpot along it:
/// F = -stiffness·(|d| - rest_length)·d̂ - damping·(v·d̂)·d̂, d = position - anchor.
/// Removed with its body.
struct SpringDef {
  BodyId body;
  Vec3 anchor = Vec3::Zero();  ///< m
  Real stiffness = 0;          ///< N/m, > 0
  Real rest_length = 0;        ///< m, >= 0
  Real damping = 0;            ///< N·s/m, >= 0
};

/// Inverse-square pull towards a point on every dynamic body whose layer is in `mask`:
/// a = -strength·d̂ / max(|d|, min_distance)², d = position - center (gravity of a point mass,
/// strength = G·M).
struct AttractorDef {
  Vec3 center = Vec3::Zero();     ///< m
  Real strength = 0;              ///< m³/s², > 0
  Real min_distance = Real(0.1);  ///< m, > 0: closer than this the pull stops growing
  std::uint32_t mask = 0xFFFFFFFFu;
};

}  // namespace ricochet::physics
