#pragma once
/// What happened during the last step, for game code (damage, sounds) to read.

#include "ricochet/physics/types.h"

namespace ricochet::physics {

/// One side of a contact: a body (shape is null) or a static shape (body is null).
struct ContactTarget {
  BodyId body;
  ShapeId shape;
};

/// Two objects started touching this step.
struct ContactBeginEvent {
  BodyId body;  ///< always a body
  ContactTarget other;
  Vec3 point;           ///< m, world
  Vec3 normal;          ///< from body towards other
  Real approach_speed;  ///< m/s, closing speed along the normal before the solve (>= 0)
};

/// Two objects stopped touching this step (or one was destroyed).
struct ContactEndEvent {
  BodyId body;
  ContactTarget other;
};

/// A touching contact and the impulse the solver applied to it this step.
struct ContactImpulseEvent {
  BodyId body;
  ContactTarget other;
  Vec3 point;
  Vec3 normal;
  Real normal_impulse;  ///< N·s, summed over substeps
};

/// A body whose state became NaN or infinite; it was restored to its state before the step and
/// frozen.
struct NonFiniteEvent {
  BodyId body;
};

}  // namespace ricochet::physics
