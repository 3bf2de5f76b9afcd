/// Integration of velocities and positions over one (sub)step, for every Integrator:
///
///   SemiImplicitEuler  v += a(x, v)·h, then (after contacts) x += v·h        symplectic
///   ExplicitEuler      a from the substep start; x += v·h, then v += a·h     reference only
///   ExactBallistic     semi-implicit, but free bodies move x += v0·h + ½a·h² (not under a force
///                      field, whose acceleration is not constant: those stay semi-implicit)
///   Rk4                free bodies take a classical Runge–Kutta step of x and v together
///
/// "Free" means no contact this step (speculative ones included): a body in contact is moved by
/// the solver's impulses, which only the Euler scheme composes with. A body that switches between
/// free and semi-implicit has its stored velocity converted (see kFlagExactVelocity). Rotation is
/// always semi-implicit: ω += I⁻¹τ·h, q += ½·(0, ω)·q·h, renormalised.

#include <cmath>

#include "math_util.h"
#include "scratch_vector.h"
#include "world_impl.h"

namespace ricochet::physics {

Vec3 WorldImpl::acceleration_of(std::uint32_t slot, const Motion& m, const Vec3& x,
                                const Vec3& v) const {
  const Vec3 gravity = state.gravity * state.bodies.gravity_scale[slot];
  if (state.forces.empty()) return gravity + state.bodies.force[slot] * m.inverse_mass;
  const Vec3 field =
      state.forces.force_on(slot, state.bodies.filter[slot].layer, m.inverse_mass, x, v);
  return gravity + (state.bodies.force[slot] + field) * m.inverse_mass;
}

namespace {

/// One classical RK4 step of dx/dt = v, dv/dt = a(x, v): the displacement and the new velocity.
template <class Acceleration>
void runge_kutta_step(const Vec3& x0, const Vec3& v0, Real h, Acceleration&& a, Vec3& move,
                      Vec3& v1) {
  const Real half_h = Real(0.5) * h;
  const Vec3 a1 = a(x0, v0);
  const Vec3 v2 = v0 + half_h * a1;
  const Vec3 a2 = a(x0 + half_h * v0, v2);
  const Vec3 v3 = v0 + half_h * a2;
  const Vec3 a3 = a(x0 + half_h * v2, v3);
  const Vec3 v4 = v0 + h * a3;
  const Vec3 a4 = a(x0 + h * v3, v4);
  const Real sixth_h = h / 6;
  move = sixth_h * (v0 + 2 * v2 + 2 * v3 + v4);
  v1 = v0 + sixth_h * (a1 + 2 * a2 + 2 * a3 + a4);
}

}  // namespace

/// Freezes a body whose velocity became non-finite (before any contact can carry the bad value
/// to a neighbour); clamps speeds to the world's limits otherwise.
void WorldImpl::clamp_or_freeze(std::uint32_t slot, Motion& m) {
  if (!is_finite(m.linear_velocity) || !is_finite(m.angular_velocity)) {
    freeze_body(slot);
    m = Motion{};
    return;
  }
  const Real v2 = m.linear_velocity.squaredNorm();
  if (v2 > def.max_linear_speed * def.max_linear_speed)
    m.linear_velocity *= def.max_linear_speed / std::sqrt(v2);
  const Real w2 = m.angular_velocity.squaredNorm();
  if (w2 > def.max_angular_speed * def.max_angular_speed)
    m.angular_velocity *= def.max_angular_speed / std::sqrt(w2);
}

bool WorldImpl::moves_exactly(std::uint32_t slot) const {
  switch (def.integrator) {
    case Integrator::Rk4:
      return scratch.contact_count[slot] == 0;
    case Integrator::ExactBallistic:
      return scratch.contact_count[slot] == 0 && !state.bodies.has(slot, kFlagKinematic) &&
             (state.forces.empty() || !state.forces.acts_on(slot, state.bodies.filter[slot].layer));
    case Integrator::SemiImplicitEuler:
    case Integrator::ExplicitEuler:
      break;
  }
  return false;
}

void WorldImpl::mark_velocity_as_given(std::uint32_t slot) {
  // A caller's velocity is the velocity at this instant: the end-of-step form when the integrator
  // can move exactly. Semi-implicit worlds take it as their mean, as they always have.
  if (def.integrator == Integrator::ExactBallistic || def.integrator == Integrator::Rk4) {
    state.bodies.flags[slot] |= kFlagExactVelocity;
  } else {
    state.bodies.flags[slot] &= static_cast<std::uint16_t>(~kFlagExactVelocity);
  }
}

void WorldImpl::convert_velocity_forms(Real h) {
  if (def.integrator != Integrator::ExactBallistic && def.integrator != Integrator::Rk4) return;
  for (const std::uint32_t slot : scratch.awake_list) {
    if (!state.bodies.simulated(slot)) continue;
    const bool exact = moves_exactly(slot);
    if (exact == state.bodies.has(slot, kFlagExactVelocity)) continue;
    // Semi-implicit Euler stores the mean velocity of the step just taken, an exact move the
    // velocity at its end: for constant a they differ by ½·a·h. Converting when a body switches
    // keeps its trajectory on the same parabola, so no energy jumps in or out.
    Motion& m = state.bodies.motion[slot];
    const Real half_h = exact ? Real(0.5) * h : Real(-0.5) * h;
    m.linear_velocity +=
        half_h * acceleration_of(slot, m, state.bodies.position[slot], m.linear_velocity);
    state.bodies.flags[slot] ^= kFlagExactVelocity;
  }
}

void WorldImpl::integrate_velocities(Real h) {
  const bool rk4 = def.integrator == Integrator::Rk4;
  scratch.solver.acceleration.resize(scratch.awake_list.size());
  if (rk4) {
    assign_reusing(scratch.solver.free_flight, scratch.awake_list.size(), 0);
    scratch.solver.free_flight_move.resize(scratch.awake_list.size());
  }
  for (std::size_t k = 0; k < scratch.awake_list.size(); ++k) {
    const std::uint32_t slot = scratch.awake_list[k];
    scratch.solver.acceleration[k].setZero();
    Motion& m = scratch.solver.bodies[k];
    if (!state.bodies.simulated(slot)) {  // kinematic, or frozen this step
      // A kinematic body keeps its velocity, within the same speed limits.
      if (!state.bodies.has(slot, kFlagFrozen)) clamp_or_freeze(slot, m);
      continue;
    }
    const Vec3 x0 = state.bodies.position[slot];
    const Vec3 v0 = m.linear_velocity;
    if (rk4 && moves_exactly(slot)) {
      const auto a = [&](const Vec3& x, const Vec3& v) { return acceleration_of(slot, m, x, v); };
      runge_kutta_step(x0, v0, h, a, scratch.solver.free_flight_move[k], m.linear_velocity);
      scratch.solver.free_flight[k] = 1;
    } else {
      scratch.solver.acceleration[k] = acceleration_of(slot, m, x0, v0);
      m.linear_velocity += h * scratch.solver.acceleration[k];
    }
    if (def.enable_rotation)
      m.angular_velocity += (h * m.inverse_inertia) * state.bodies.torque[slot];
    clamp_or_freeze(slot, m);
  }
}

void WorldImpl::evaluate_accelerations() {
  scratch.solver.acceleration.resize(scratch.awake_list.size());
  for (std::size_t k = 0; k < scratch.awake_list.size(); ++k) {
    const std::uint32_t slot = scratch.awake_list[k];
    scratch.solver.acceleration[k].setZero();
    if (!state.bodies.simulated(slot)) continue;
    const Motion& m = scratch.solver.bodies[k];
    scratch.solver.acceleration[k] =
        acceleration_of(slot, m, state.bodies.position[slot], m.linear_velocity);
  }
}

void WorldImpl::apply_accelerations(Real h) {
  for (std::size_t k = 0; k < scratch.awake_list.size(); ++k) {
    const std::uint32_t slot = scratch.awake_list[k];
    if (!state.bodies.simulated(slot)) continue;
    Motion& m = scratch.solver.bodies[k];
    m.linear_velocity += h * scratch.solver.acceleration[k];
    if (def.enable_rotation)
      m.angular_velocity += (h * m.inverse_inertia) * state.bodies.torque[slot];
    clamp_or_freeze(slot, m);
  }
}

void WorldImpl::integrate_positions(Real h) {
  const bool split = def.position_correction == PositionCorrection::SplitImpulse;
  const bool ballistic = def.integrator == Integrator::ExactBallistic;
  const bool rk4 = def.integrator == Integrator::Rk4;
  for (std::size_t k = 0; k < scratch.awake_list.size(); ++k) {
    const std::uint32_t slot = scratch.awake_list[k];
    if (state.bodies.has(slot, kFlagFrozen)) continue;
    const Motion& m = scratch.solver.bodies[k];
    Vec3 move = m.linear_velocity * h;
    if (rk4 && scratch.solver.free_flight[k]) move = scratch.solver.free_flight_move[k];
    if (split) {
      move += scratch.solver.pseudo_velocity[k] * h;
      scratch.solver.pseudo_velocity[k].setZero();
    }
    if (ballistic && moves_exactly(slot)) {
      // v already includes a·h, so x + v·h - ½a·h² = x + v0·h + ½a·h²: exact for constant a.
      move -= scratch.solver.acceleration[k] * (Real(0.5) * h * h);
    }
    state.bodies.position[slot] += move;
    scratch.solver.delta_position[k] += move;
    const Vec3& w = m.angular_velocity;
    if (def.enable_rotation && (w.x() != 0 || w.y() != 0 || w.z() != 0)) {
      Quat& q = state.bodies.orientation[slot];
      const Quat dq = Quat(0, w.x(), w.y(), w.z()) * q;
      const Real half_h = Real(0.5) * h;
      q = Quat(q.w() + half_h * dq.w(), q.x() + half_h * dq.x(), q.y() + half_h * dq.y(),
               q.z() + half_h * dq.z());
      q.normalize();
    }
  }
}

}  // namespace ricochet::physics
