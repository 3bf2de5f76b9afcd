#pragma once
/// What happened during the last step, for game code (damage, sounds) to read.

#include <cstdint>

#include "ricochet/physics/types.h"

namespace ricochet::physics {

/// One side of a contact, or what a query or projectile hit: a body (shape is null) or a static
/// shape (body is null).
struct ContactTarget {
  BodyId body;
  ShapeId shape;
  std::uint64_t user_data = 0;  ///< the body's BodyDef::user_data (0 for a static shape)
};

/// Two objects started touching this step.
struct ContactBeginEvent {
  BodyId body;  ///< always a body
  ContactTarget other;
  Vec3 point;                   ///< m, world
  Vec3 normal;                  ///< from body towards other
  Real approach_speed;          ///< m/s, closing speed along the normal before the solve (>= 0)
  std::uint64_t user_data = 0;  ///< body's BodyDef::user_data
};

/// Two objects stopped touching this step (or one was destroyed).
struct ContactEndEvent {
  BodyId body;
  ContactTarget other;
  std::uint64_t user_data = 0;  ///< body's BodyDef::user_data
};

/// A touching contact and the impulse the solver applied to it this step.
struct ContactImpulseEvent {
  BodyId body;
  ContactTarget other;
  Vec3 point;
  Vec3 normal;
  Real normal_impulse;          ///< N·s, summed over substeps
  std::uint64_t user_data = 0;  ///< body's BodyDef::user_data
};

/// A body whose state became NaN or infinite; it was restored to its state before the step and
/// frozen.
struct NonFiniteEvent {
  BodyId body;
};

/// A body a snapshot must send again after the last step, as Box2D's b2BodyMoveEvent: it moved
/// during the step, was moved, created or woken since the step before, or fell asleep. Bodies
/// that stayed put (sleeping, or awake at rest) report nothing. Reported in slot order.
struct BodyMoveEvent {
  BodyId body;
  Vec3 position;                ///< m, after the step
  Quat orientation;             ///< unit, after the step
  std::uint64_t user_data = 0;  ///< BodyDef::user_data
  bool fell_asleep = false;     ///< it sleeps now, and reports nothing more until it wakes
  bool woke = false;  ///< it was asleep, and woke since the step before or during this one
};

}  // namespace ricochet::physics
