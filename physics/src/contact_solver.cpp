/// Sequential impulses over sphere contacts, with integration, per (sub)step:
///
///   prepare → for each substep { integrate velocities → warm start → iterate (biased)
///             → integrate positions → relax (unbiased, SoftStep) } → restitution
///
/// Accumulated impulses are clamped (normal >= 0, friction inside the Coulomb circle, rolling
/// inside its torque limit) and carried across steps for warm starting. Position error is removed
/// by the chosen PositionCorrection. Friction is one 2-D impulse in the tangent plane clamped to
/// a circle (isotropic Coulomb), equivalent to two tangent rows without the box-clamp bias.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include "math_util.h"
#include "world_impl.h"

namespace ricochet::physics {

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

/// Box2D v3 soft constraint coefficients for a contact spring of `hertz` with damping `zeta`.
struct Softness {
  Real bias_rate = 0;
  Real mass_scale = 1;
  Real impulse_scale = 0;
};

Softness make_softness(Real hertz, Real zeta, Real h) {
  if (hertz <= 0) return {};
  const Real omega = 2 * std::numbers::pi_v<Real> * hertz;
  const Real a1 = 2 * zeta + h * omega;
  const Real a2 = h * omega * a1;
  const Real a3 = 1 / (1 + a2);
  return {omega / a1, a2 * a3, a3};
}

/// Parameters of one pass over the contacts.
struct PassParams {
  Real inverse_h;
  Real slop;
  Real baumgarte;
  Real max_correction_speed;
  Softness soft;
};

/// The other side of a static contact: never moves.
struct StaticSide {
  static constexpr Real inverse_mass = 0;
  static constexpr Real inverse_inertia = 0;
};

/// One contact row set: rolling, friction, normal (normal last: it matters most).
/// kPair: b is a body; otherwise b is static (zero velocity).
template <bool kPair, PositionCorrection kMethod, bool kUseBias, bool kTrackDelta, bool kRolling>
void solve_contact(Contact& c, Motion& A, Motion* B_ptr, const Vec3* delta_position,
                   Vec3* pseudo_velocity, const PassParams& p) {
  const Vec3 n = c.normal;
  const Vec3 zero = Vec3::Zero();
  const Vec3& vb = kPair ? B_ptr->linear_velocity : zero;
  const Vec3& wb = kPair ? B_ptr->angular_velocity : zero;
  const Real mb = kPair ? B_ptr->inverse_mass : Real(0);
  const Real ib = kPair ? B_ptr->inverse_inertia : Real(0);
  Vec3 va = A.linear_velocity, wa = A.angular_velocity;
  Vec3 vb_new = vb, wb_new = wb;
  const Real ma = A.inverse_mass, ia = A.inverse_inertia;

  if constexpr (kRolling) {
    if (c.rolling > 0) {
      const Real limit = c.rolling * c.normal_impulse;
      const Vec3 dw = wb_new - wa;
      Vec3 accumulated = c.rolling_impulse - c.rolling_mass * dw;
      const Real len2 = accumulated.squaredNorm();
      if (len2 > limit * limit) accumulated *= limit / std::sqrt(len2);
      const Vec3 impulse = accumulated - c.rolling_impulse;
      c.rolling_impulse = accumulated;
      wa -= ia * impulse;
      wb_new += ib * impulse;
    }
  }

  {  // Friction: relative tangential velocity at the contact point.
    const Vec3 dv = vb_new - va - (c.ra * wa + c.rb * wb_new).cross(n);
    const Vec3 vt = dv - n * n.dot(dv);
    const Real limit = c.friction * c.normal_impulse;
    Vec3 accumulated = c.friction_impulse - c.tangent_mass * vt;
    const Real len2 = accumulated.squaredNorm();
    if (len2 > limit * limit) accumulated *= len2 > 0 ? limit / std::sqrt(len2) : Real(0);
    const Vec3 impulse = accumulated - c.friction_impulse;
    c.friction_impulse = accumulated;
    const Vec3 torque_dir = n.cross(impulse);
    va -= ma * impulse;
    wa -= (ia * c.ra) * torque_dir;
    vb_new += mb * impulse;
    wb_new -= (ib * c.rb) * torque_dir;
  }

  {  // Normal.
    Real s = c.separation;
    if constexpr (kTrackDelta) {
      s += n.dot((kPair ? delta_position[c.b] : zero) - delta_position[c.a]);
    }
    Real bias = 0, mass_scale = 1, impulse_scale = 0;
    if (s > 0) {
      bias = s * p.inverse_h;  // speculative: may close the gap this step, no further
    } else if constexpr (kUseBias) {
      if constexpr (kMethod == PositionCorrection::Baumgarte) {
        bias = std::max(p.baumgarte * p.inverse_h * std::min(s + p.slop, Real(0)), -p.max_correction_speed);
      } else if constexpr (kMethod == PositionCorrection::SoftStep) {
        bias = std::max(p.soft.bias_rate * s, -p.max_correction_speed);
        mass_scale = p.soft.mass_scale;
        impulse_scale = p.soft.impulse_scale;
      }
    }
    const Real vn = n.dot(vb_new - va);
    const Real impulse = -c.normal_mass * mass_scale * (vn + bias) - impulse_scale * c.normal_impulse;
    const Real accumulated = std::max(c.normal_impulse + impulse, Real(0));
    const Real applied = accumulated - c.normal_impulse;
    c.normal_impulse = accumulated;
    c.max_normal_impulse = std::max(c.max_normal_impulse, accumulated);
    va -= (ma * applied) * n;
    vb_new += (mb * applied) * n;

    if constexpr (kMethod == PositionCorrection::SplitImpulse && kUseBias) {
      // Pseudo-velocities push penetrating bodies apart without adding momentum.
      const Real depth = s + p.slop;
      if (depth < 0 || c.pseudo_impulse > 0) {
        const Vec3& pa = pseudo_velocity[c.a];
        const Real pvn = n.dot((kPair ? pseudo_velocity[c.b] : zero) - pa);
        const Real target = std::min(-p.baumgarte * p.inverse_h * std::min(depth, Real(0)), p.max_correction_speed);
        const Real pseudo = std::max(c.pseudo_impulse - c.normal_mass * (pvn - target), Real(0));
        const Real pseudo_applied = pseudo - c.pseudo_impulse;
        c.pseudo_impulse = pseudo;
        pseudo_velocity[c.a] -= (ma * pseudo_applied) * n;
        if constexpr (kPair) pseudo_velocity[c.b] += (mb * pseudo_applied) * n;
      }
    }
  }

  A.linear_velocity = va;
  A.angular_velocity = wa;
  if constexpr (kPair) {
    B_ptr->linear_velocity = vb_new;
    B_ptr->angular_velocity = wb_new;
  }
}

template <PositionCorrection kMethod, bool kUseBias, bool kTrackDelta, bool kRolling>
void solve_all(std::vector<Contact>& pair_contacts, std::vector<Contact>& static_contacts,
               std::vector<Motion>& motion, const Vec3* delta_position, Vec3* pseudo_velocity,
               const PassParams& p) {
  Motion* m = motion.data();
  for (Contact& c : pair_contacts) {
    solve_contact<true, kMethod, kUseBias, kTrackDelta, kRolling>(c, m[c.a], &m[c.b], delta_position,
                                                                  pseudo_velocity, p);
  }
  for (Contact& c : static_contacts) {
    solve_contact<false, kMethod, kUseBias, kTrackDelta, kRolling>(c, m[c.a], nullptr, delta_position,
                                                                   pseudo_velocity, p);
  }
}

template <PositionCorrection kMethod, bool kUseBias>
void solve_all_dispatch(bool track_delta, bool rolling, std::vector<Contact>& pair_contacts,
                        std::vector<Contact>& static_contacts, std::vector<Motion>& motion,
                        const Vec3* delta_position, Vec3* pseudo_velocity, const PassParams& p) {
  if (track_delta) {
    if (rolling) {
      solve_all<kMethod, kUseBias, true, true>(pair_contacts, static_contacts, motion, delta_position, pseudo_velocity, p);
    } else {
      solve_all<kMethod, kUseBias, true, false>(pair_contacts, static_contacts, motion, delta_position, pseudo_velocity, p);
    }
  } else if (rolling) {
    solve_all<kMethod, kUseBias, false, true>(pair_contacts, static_contacts, motion, delta_position, pseudo_velocity, p);
  } else {
    solve_all<kMethod, kUseBias, false, false>(pair_contacts, static_contacts, motion, delta_position, pseudo_velocity, p);
  }
}

}  // namespace

void WorldImpl::prepare_contacts() {
  const auto prepare = [&](Contact& c, const Motion& A, const Motion* B) {
    const Real mb = B ? B->inverse_mass : Real(0);
    const Real ib = B ? B->inverse_inertia : Real(0);
    const Real mass_sum = A.inverse_mass + mb;
    c.normal_mass = mass_sum > 0 ? 1 / mass_sum : Real(0);
    const Real tangent_sum = mass_sum + A.inverse_inertia * c.ra * c.ra + ib * c.rb * c.rb;
    c.tangent_mass = tangent_sum > 0 ? 1 / tangent_sum : Real(0);
    const Real rolling_sum = A.inverse_inertia + ib;
    c.rolling_mass = rolling_sum > 0 ? 1 / rolling_sum : Real(0);
    const Vec3 vb = B ? B->linear_velocity : Vec3::Zero().eval();
    c.relative_velocity = c.normal.dot(vb - A.linear_velocity);
    c.friction_impulse -= c.normal * c.normal.dot(c.friction_impulse);
    c.max_normal_impulse = 0;
    c.total_normal_impulse = 0;
    c.pseudo_impulse = 0;
  };
  auto& motion = bodies.motion;
  for (Contact& c : pair_contacts) prepare(c, motion[c.a], &motion[c.b]);
  for (Contact& c : static_contacts) prepare(c, motion[c.a], nullptr);
}

void WorldImpl::warm_start() {
  auto& motion = bodies.motion;
  const auto apply = [](const Contact& c, Motion& A, Motion* B) {
    const Vec3 linear = c.normal * c.normal_impulse + c.friction_impulse;
    const Vec3 torque_dir = c.normal.cross(c.friction_impulse);
    A.linear_velocity -= A.inverse_mass * linear;
    A.angular_velocity -= A.inverse_inertia * (c.ra * torque_dir + c.rolling_impulse);
    if (B) {
      B->linear_velocity += B->inverse_mass * linear;
      B->angular_velocity += B->inverse_inertia * (c.rolling_impulse - c.rb * torque_dir);
    }
  };
  for (const Contact& c : pair_contacts) apply(c, motion[c.a], &motion[c.b]);
  for (const Contact& c : static_contacts) apply(c, motion[c.a], nullptr);
}

void WorldImpl::reset_for_solve() {
  for (Contact& c : pair_contacts) {
    c.normal_impulse = 0;
    c.friction_impulse.setZero();
    c.rolling_impulse.setZero();
  }
  for (Contact& c : static_contacts) {
    c.normal_impulse = 0;
    c.friction_impulse.setZero();
    c.rolling_impulse.setZero();
  }
}

void WorldImpl::solve_contacts(Real h, bool use_bias) {
  PassParams p;
  p.inverse_h = 1 / h;
  p.slop = def.linear_slop;
  p.baumgarte = def.baumgarte;
  p.max_correction_speed = def.max_correction_speed;
  p.soft = make_softness(std::min(def.contact_hertz, Real(0.25) / h), def.contact_damping_ratio, h);
  const bool track_delta = def.substeps > 1;
  bool rolling = false;
  for (const std::uint32_t slot : awake_list) {
    if (bodies.material[slot].rolling_resistance > 0) {
      rolling = true;
      break;
    }
  }
  const Vec3* delta = delta_position.data();
  Vec3* pseudo = pseudo_velocity.data();
  auto& motion = bodies.motion;
  switch (def.position_correction) {
    case PositionCorrection::Baumgarte:
      if (use_bias) {
        solve_all_dispatch<PositionCorrection::Baumgarte, true>(track_delta, rolling, pair_contacts, static_contacts, motion, delta, pseudo, p);
      } else {
        solve_all_dispatch<PositionCorrection::Baumgarte, false>(track_delta, rolling, pair_contacts, static_contacts, motion, delta, pseudo, p);
      }
      break;
    case PositionCorrection::SplitImpulse:
      if (use_bias) {
        solve_all_dispatch<PositionCorrection::SplitImpulse, true>(track_delta, rolling, pair_contacts, static_contacts, motion, delta, pseudo, p);
      } else {
        solve_all_dispatch<PositionCorrection::SplitImpulse, false>(track_delta, rolling, pair_contacts, static_contacts, motion, delta, pseudo, p);
      }
      break;
    case PositionCorrection::SoftStep:
      if (use_bias) {
        solve_all_dispatch<PositionCorrection::SoftStep, true>(track_delta, rolling, pair_contacts, static_contacts, motion, delta, pseudo, p);
      } else {
        solve_all_dispatch<PositionCorrection::SoftStep, false>(track_delta, rolling, pair_contacts, static_contacts, motion, delta, pseudo, p);
      }
      break;
  }
}

void WorldImpl::apply_restitution() {
  const Real threshold = def.restitution_threshold;
  auto& motion = bodies.motion;
  const auto apply = [&](Contact& c, Motion& A, Motion* B) {
    if (c.restitution == 0 || c.relative_velocity > -threshold || c.max_normal_impulse == 0) return;
    const Vec3 vb = B ? B->linear_velocity : Vec3::Zero().eval();
    const Real vn = c.normal.dot(vb - A.linear_velocity);
    const Real impulse = -c.normal_mass * (vn + c.restitution * c.relative_velocity);
    const Real accumulated = std::max(c.normal_impulse + impulse, Real(0));
    const Real applied = accumulated - c.normal_impulse;
    c.normal_impulse = accumulated;
    c.max_normal_impulse = std::max(c.max_normal_impulse, accumulated);
    c.total_normal_impulse += applied;
    A.linear_velocity -= (A.inverse_mass * applied) * c.normal;
    if (B) B->linear_velocity += (B->inverse_mass * applied) * c.normal;
  };
  for (Contact& c : pair_contacts) apply(c, motion[c.a], &motion[c.b]);
  for (Contact& c : static_contacts) apply(c, motion[c.a], nullptr);
}

void WorldImpl::integrate_velocities(Real h) {
  const Real max_linear2 = def.max_linear_speed * def.max_linear_speed;
  const Real max_angular2 = def.max_angular_speed * def.max_angular_speed;
  for (const std::uint32_t slot : awake_list) {
    if (!bodies.simulated(slot)) continue;  // kinematic or frozen this step
    Motion& m = bodies.motion[slot];
    m.linear_velocity += h * (def.gravity * bodies.gravity_scale[slot] + bodies.force[slot] * m.inverse_mass);
    m.angular_velocity += (h * m.inverse_inertia) * bodies.torque[slot];
    if (!is_finite(m.linear_velocity) || !is_finite(m.angular_velocity)) {
      freeze_body(slot);  // before any contact can carry the bad value to a neighbour
      continue;
    }
    const Real v2 = m.linear_velocity.squaredNorm();
    if (v2 > max_linear2) m.linear_velocity *= def.max_linear_speed / std::sqrt(v2);
    const Real w2 = m.angular_velocity.squaredNorm();
    if (w2 > max_angular2) m.angular_velocity *= def.max_angular_speed / std::sqrt(w2);
  }
}

void WorldImpl::integrate_positions(Real h) {
  const bool split = def.position_correction == PositionCorrection::SplitImpulse;
  const bool ballistic = def.integrator == Integrator::ExactBallistic;
  for (const std::uint32_t slot : awake_list) {
    if (bodies.has(slot, kFlagFrozen)) continue;
    const Motion& m = bodies.motion[slot];
    Vec3 move = m.linear_velocity * h;
    if (split) {
      move += pseudo_velocity[slot] * h;
      pseudo_velocity[slot].setZero();
    }
    if (ballistic && contact_count[slot] == 0 && !bodies.has(slot, kFlagKinematic)) {
      // v already includes a·h, so x + v·h - ½a·h² = x + v0·h + ½a·h²: exact for constant a.
      const Vec3 acceleration = def.gravity * bodies.gravity_scale[slot] + bodies.force[slot] * m.inverse_mass;
      move -= acceleration * (Real(0.5) * h * h);
    }
    bodies.position[slot] += move;
    delta_position[slot] += move;
    const Vec3& w = m.angular_velocity;
    if (w.x() != 0 || w.y() != 0 || w.z() != 0) {
      Quat& q = bodies.orientation[slot];
      const Quat spin(0, w.x(), w.y(), w.z());
      const Quat dq = spin * q;
      const Real half_h = Real(0.5) * h;
      q = Quat(q.w() + half_h * dq.w(), q.x() + half_h * dq.x(), q.y() + half_h * dq.y(),
               q.z() + half_h * dq.z());
      q.normalize();
    }
  }
}

void WorldImpl::solve(Real step_dt) {
  const auto start = Clock::now();
  double integrate_ms = 0;
  const int substeps = def.substeps;
  const Real h = step_dt / static_cast<Real>(substeps);
  const bool explicit_euler = def.integrator == Integrator::ExplicitEuler;
  const bool relax = def.position_correction == PositionCorrection::SoftStep;
  prepare_contacts();
  if (!def.warm_starting) reset_for_solve();
  const auto timed_integrate_velocities = [&] {
    const auto t0 = Clock::now();
    integrate_velocities(h);
    integrate_ms += ms_since(t0);
  };
  for (int sub = 0; sub < substeps; ++sub) {
    if (!explicit_euler) timed_integrate_velocities();
    if (def.warm_starting) {
      warm_start();
    } else if (sub > 0) {
      reset_for_solve();
    }
    for (int i = 0; i < def.iterations; ++i) solve_contacts(h, true);
    const auto t0 = Clock::now();
    integrate_positions(h);
    integrate_ms += ms_since(t0);
    if (relax) {
      for (int i = 0; i < def.relax_iterations; ++i) solve_contacts(h, false);
    }
    if (explicit_euler) timed_integrate_velocities();
    for (Contact& c : pair_contacts) c.total_normal_impulse += c.normal_impulse;
    for (Contact& c : static_contacts) c.total_normal_impulse += c.normal_impulse;
  }
  apply_restitution();
  profile.integrate_ms = integrate_ms;
  profile.solve_ms = ms_since(start) - integrate_ms;
}

}  // namespace ricochet::physics
