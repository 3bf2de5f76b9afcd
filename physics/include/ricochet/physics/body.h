#pragma once
/// Body definitions and the read-only view of a body's state.

#include <cstdint>

#include "ricochet/physics/types.h"

namespace ricochet::physics {

enum class BodyType : std::uint8_t {
  Dynamic,    ///< moved by forces, gravity and contacts
  Kinematic,  ///< moved by game code through its velocity; pushes dynamic bodies, is never pushed
};

/// Moment of inertia model of a sphere. Both are isotropic, so the world inertia equals the local.
enum class InertiaModel : std::uint8_t {
  SolidSphere,   ///< I = 2/5 m r²
  HollowSphere,  ///< I = 2/3 m r² (thin shell)
};

/// Surface response. When two surfaces touch, restitution takes the larger value, friction and
/// rolling resistance the geometric mean.
struct Material {
  Real restitution = 0;       ///< 0 (no bounce) to 1 (elastic)
  Real friction = Real(0.6);  ///< Coulomb coefficient, >= 0
  Real rolling_resistance =
      0;  ///< dimensionless: resisting torque = coefficient * radius * normal force
};

/// Collision filter: two objects collide when each one's layer is in the other's mask.
struct Filter {
  std::uint32_t layer = 1;
  std::uint32_t mask = 0xFFFFFFFFu;
};

/// Everything needed to create a sphere body. Defaults give a 1 kg, 0.5 m radius solid sphere at
/// rest at the origin.
struct BodyDef {
  BodyType type = BodyType::Dynamic;
  Vec3 position = Vec3::Zero();          ///< m
  Quat orientation = Quat::Identity();   ///< normalised on creation
  Vec3 linear_velocity = Vec3::Zero();   ///< m/s
  Vec3 angular_velocity = Vec3::Zero();  ///< rad/s
  Real radius = Real(0.5);               ///< m, > 0
  Real mass = 1;                         ///< kg, > 0 (ignored for kinematic bodies)
  InertiaModel inertia = InertiaModel::SolidSphere;
  Material material{};
  Filter filter{};
  Real gravity_scale = 1;      ///< multiplies the world gravity
  bool lock_rotation = false;  ///< infinite inertia: the body never spins
  bool fast = false;           ///< continuous collision (swept tests) against statics and bodies
  bool sensor = false;  ///< reports begin/end events with overlapping bodies (not statics); never
                        ///< pushes or is pushed
  bool allow_sleep = true;
  std::uint64_t user_data = 0;
};

/// Snapshot of a body's state as seen between steps.
struct BodyState {
  BodyType type = BodyType::Dynamic;
  Vec3 position = Vec3::Zero();
  Quat orientation = Quat::Identity();
  Vec3 linear_velocity = Vec3::Zero();
  Vec3 angular_velocity = Vec3::Zero();
  Vec3 force = Vec3::Zero();   ///< N, accumulated since the last step
  Vec3 torque = Vec3::Zero();  ///< N·m, accumulated since the last step
  Real radius = 0;
  Real inverse_mass = 0;                      ///< 1/kg, 0 for kinematic bodies
  Mat3 inverse_inertia_world = Mat3::Zero();  ///< 1/(kg·m²)
  bool sleeping = false;
  bool frozen = false;  ///< stopped after its state became non-finite
  std::uint64_t user_data = 0;
};

}  // namespace ricochet::physics
