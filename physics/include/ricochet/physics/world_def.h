#pragma once
/// World configuration: gravity, solver and integrator choices, limits.

#include <cstdint>
#include <string>

#include "ricochet/physics/types.h"

namespace ricochet::physics {

/// How contact penetration is removed.
enum class PositionCorrection : std::uint8_t {
  Baumgarte,     ///< velocity bias beta/dt * depth (the classic; adds energy when it corrects)
  SplitImpulse,  ///< separate pseudo-velocities that move positions but never carry momentum
  SoftStep,      ///< soft contacts with substepping and relaxation (Box2D v3 "soft step")
};

/// How velocity and position advance over a (sub)step.
enum class Integrator : std::uint8_t {
  ExplicitEuler,      ///< x += v·dt, then v += a·dt (reference only; gains energy)
  SemiImplicitEuler,  ///< v += a·dt, then x += v·dt (symplectic; the default)
  /// Semi-implicit, but bodies without contacts follow x + v·dt + ½a·dt² (exact when the
  /// acceleration is constant over the step: gravity and applied forces). Bodies under a force
  /// field stay semi-implicit (the term would pump energy into a spring or an orbit).
  ExactBallistic,
  /// Classical 4th-order Runge–Kutta for bodies without contacts (gravity, applied forces and
  /// force fields evaluated at every stage); semi-implicit Euler for bodies in contact.
  Rk4,
};

struct WorldDef {
  Vec3 gravity = Vec3(0, Real(-9.81), 0);  ///< m/s²
  /// Baumgarte by measurement: at 1 substep it holds the rain pile to the slop at the least cost;
  /// SoftStep wants substeps >= 4.
  PositionCorrection position_correction = PositionCorrection::Baumgarte;
  Integrator integrator = Integrator::SemiImplicitEuler;
  int iterations = 10;              ///< velocity iterations per substep, 1..1000
  int relax_iterations = 1;         ///< unbiased iterations per substep (SoftStep only), 0..1000
  int substeps = 1;                 ///< 1..64
  Real baumgarte = Real(0.2);       ///< Baumgarte factor beta, 0..1
  Real linear_slop = Real(0.005);   ///< m, penetration allowed without correction
  Real max_correction_speed = 4;    ///< m/s, cap on position-correction velocity
  Real contact_hertz = 30;          ///< SoftStep contact stiffness, Hz
  Real contact_damping_ratio = 10;  ///< SoftStep contact damping ratio
  Real restitution_threshold = 1;   ///< m/s, slower impacts do not bounce
  Real max_speculative_distance = Real(0.25);  ///< m, largest gap at which a contact is created
  Real max_linear_speed = 10000;               ///< m/s, velocities are clamped to this
  Real max_angular_speed = 1000;               ///< rad/s
  bool warm_starting = true;
  /// A last pass per substep from the ground up in which each contact's supporting body is
  /// immovable: heavy-on-light stacks hold at any mass ratio (sequential impulses alone need
  /// about `ratio` iterations). It runs only in steps where some contact joins two dynamic
  /// bodies whose masses differ by more than shock_mass_ratio, and then costs a breadth-first
  /// pass over the contact graph and one scalar pass over the contacts.
  bool shock_propagation = true;
  Real shock_mass_ratio = 4;  ///< 1..1e9; at 1 any two touching bodies of unequal mass trigger it
  bool enable_sleep = true;
  Real sleep_linear_speed = Real(0.05);  ///< m/s, below this a body may sleep
  Real sleep_angular_speed = Real(0.1);  ///< rad/s
  Real time_to_sleep = Real(0.5);        ///< s an island must stay slow before it sleeps
  bool enable_continuous = true;         ///< swept tests for bodies flagged fast

  // Features a scene may not need (see scene_profile.h). Off costs nothing in the step: the
  // solver runs a kernel without that feature rather than a branch per contact.
  /// Off: no body spins. Contacts apply no torque, torques and angular velocities are ignored and
  /// orientations stay as set (players are spheres that need no spin).
  bool enable_rotation = true;
  bool enable_friction = true;            ///< off: contacts push along the normal only
  bool enable_rolling_resistance = true;  ///< off: Material::rolling_resistance is ignored
  bool enable_restitution = true;         ///< off: Material::restitution is ignored (no bounce)
  bool contact_events = true;             ///< fill begin/end/impulse event lists each step
  /// Solve contacts with AVX2 when the CPU has it. Results are bit-identical either way; off
  /// only to measure the baseline (SSE2/NEON) path.
  bool wide_simd = true;
  std::uint32_t max_bodies = 1u << 22;
  std::uint32_t max_shapes = 1u << 20;
  std::uint32_t max_projectiles = 1u << 20;

  /// Empty when valid; otherwise says which field is wrong and what it must be.
  std::string validate() const;
};

}  // namespace ricochet::physics
