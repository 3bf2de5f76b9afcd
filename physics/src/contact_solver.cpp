/// Sequential impulses over sphere contacts, with integration, per (sub)step:
///
///   prepare → for each substep { integrate velocities → warm start → iterate (biased)
///             → integrate positions → relax (unbiased, SoftStep) } → restitution → store impulses
///
/// Accumulated impulses are clamped (normal >= 0, friction inside the Coulomb circle, rolling
/// inside its torque limit) and carried across steps for warm starting. Position error is removed
/// by the chosen PositionCorrection. Friction is one 2-D impulse in the tangent plane clamped to a
/// circle (isotropic Coulomb), equivalent to two tangent rows without the box-clamp bias.
/// Spheres touch on the line between centres, so the normal impulse has no torque.

#include <algorithm>
#include <cmath>
#include <numbers>
#include <type_traits>

#include "contact_simd.h"
#include "math_util.h"
#include "scratch_vector.h"
#include "world_impl.h"

namespace ricochet::physics {

namespace {

using namespace simd;

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

// ---------------------------------------------------------------------------------------------
// The kernel.

/// The lanes' bodies: velocities and inverse masses, and with spin the angular part too.
template <class V, bool kSpin>
[[gnu::always_inline]] inline BodyVectors<V> gather_motion(const Motion* bodies,
                                                           const std::uint32_t* index) {
  if constexpr (kSpin) {
    return gather<V>(bodies, index);
  } else {
    return gather_linear<V>(bodies, index);
  }
}
template <bool kSpin, class V>
[[gnu::always_inline]] inline void scatter_motion(Motion* bodies, const std::uint32_t* index,
                                                  const BodyVectors<V>& v) {
  if constexpr (kSpin) {
    scatter(bodies, index, v);
  } else {
    scatter_linear(bodies, index, v);
  }
}

/// Solves lanes first .. first + W of block k: rolling, friction, then normal (normal last: it
/// matters most).
template <class V, ContactModel kModel, PositionCorrection kMethod, bool kUseBias, bool kTrackDelta>
[[gnu::always_inline]] inline void solve_lanes(SolverScratch& s, std::size_t k, int first,
                                               const PassParams& p) {
  constexpr bool kSpin = kModel == ContactModel::Spin || kModel == ContactModel::SpinRolling;
  constexpr bool kFriction = kModel != ContactModel::Normal;
  constexpr bool kRolling = kModel == ContactModel::SpinRolling;
  Motion* sb = s.bodies.data();
  ContactBlock& c = s.blocks[k];
  const std::uint32_t* ia = c.a + first;
  const std::uint32_t* ib = c.b + first;
  BodyVectors<V> A = gather_motion<V, kSpin>(sb, ia), B = gather_motion<V, kSpin>(sb, ib);
  const V nx = get<V>(c.nx, first), ny = get<V>(c.ny, first), nz = get<V>(c.nz, first);
  [[maybe_unused]] const V ra = get<V>(c.ra, first), rb = get<V>(c.rb, first);
  const V normal_impulse = get<V>(c.normal_impulse, first);

  if constexpr (kRolling) {
    RollingBlock& r = s.rolling[k];
    const V limit = get<V>(r.limit, first) * normal_impulse;
    const V mass = get<V>(r.mass, first);
    const V x0 = get<V>(r.x, first), y0 = get<V>(r.y, first), z0 = get<V>(r.z, first);
    V x = x0 - mass * (B.wx - A.wx);
    V y = y0 - mass * (B.wy - A.wy);
    V z = z0 - mass * (B.wz - A.wz);
    const V scale = circle_clamp_scale(x * x + y * y + z * z, limit);
    x *= scale, y *= scale, z *= scale;
    const V ix = x - x0, iy = y - y0, iz = z - z0;
    put(r.x, first, x), put(r.y, first, y), put(r.z, first, z);
    A.wx -= A.i * ix, A.wy -= A.i * iy, A.wz -= A.i * iz;
    B.wx += B.i * ix, B.wy += B.i * iy, B.wz += B.i * iz;
  }

  if constexpr (kFriction) {  // on the relative tangential velocity at the contact point
    V dvx = B.vx - A.vx, dvy = B.vy - A.vy, dvz = B.vz - A.vz;
    if constexpr (kSpin) {
      const V sx = ra * A.wx + rb * B.wx;
      const V sy = ra * A.wy + rb * B.wy;
      const V sz = ra * A.wz + rb * B.wz;
      dvx -= sy * nz - sz * ny;
      dvy -= sz * nx - sx * nz;
      dvz -= sx * ny - sy * nx;
    }
    const V dvn = dvx * nx + dvy * ny + dvz * nz;
    const V tangent_mass = get<V>(c.tangent_mass, first);
    const V fx0 = get<V>(c.fx, first), fy0 = get<V>(c.fy, first), fz0 = get<V>(c.fz, first);
    V fx = fx0 - tangent_mass * (dvx - nx * dvn);
    V fy = fy0 - tangent_mass * (dvy - ny * dvn);
    V fz = fz0 - tangent_mass * (dvz - nz * dvn);
    const V scale =
        circle_clamp_scale(fx * fx + fy * fy + fz * fz, get<V>(c.friction, first) * normal_impulse);
    fx *= scale, fy *= scale, fz *= scale;
    const V ix = fx - fx0, iy = fy - fy0, iz = fz - fz0;
    put(c.fx, first, fx), put(c.fy, first, fy), put(c.fz, first, fz);
    A.vx -= A.m * ix, A.vy -= A.m * iy, A.vz -= A.m * iz;
    B.vx += B.m * ix, B.vy += B.m * iy, B.vz += B.m * iz;
    if constexpr (kSpin) {
      const V tx = ny * iz - nz * iy, ty = nz * ix - nx * iz, tz = nx * iy - ny * ix;
      const V ka = A.i * ra, kb = B.i * rb;
      A.wx -= ka * tx, A.wy -= ka * ty, A.wz -= ka * tz;
      B.wx -= kb * tx, B.wy -= kb * ty, B.wz -= kb * tz;
    }
  }

  {  // Normal.
    V separation = get<V>(c.separation, first);
    if constexpr (kTrackDelta)
      separation += normal_difference(s.delta_position.data(), ia, ib, nx, ny, nz);
    const auto speculative = separation > 0;
    V bias = separation * p.inverse_h;  // speculative: may close the gap, no further
    V mass_scale = splat<V>(1), impulse_scale = splat<V>(0);
    if constexpr (kUseBias && kMethod == PositionCorrection::Baumgarte) {
      const V correction =
          max_v(p.baumgarte * p.inverse_h * min_v(separation + p.slop, splat<V>(0)),
                splat<V>(-p.max_correction_speed));
      bias = speculative ? bias : correction;
    } else if constexpr (kUseBias && kMethod == PositionCorrection::SoftStep) {
      const V correction = max_v(p.soft.bias_rate * separation, splat<V>(-p.max_correction_speed));
      bias = speculative ? bias : correction;
      mass_scale = speculative ? mass_scale : splat<V>(p.soft.mass_scale);
      impulse_scale = speculative ? impulse_scale : splat<V>(p.soft.impulse_scale);
    } else {
      bias = speculative ? bias : splat<V>(0);
    }
    const V normal_mass = get<V>(c.normal_mass, first);
    const V vn = (B.vx - A.vx) * nx + (B.vy - A.vy) * ny + (B.vz - A.vz) * nz;
    const V impulse = -normal_mass * mass_scale * (vn + bias) - impulse_scale * normal_impulse;
    const V accumulated = max_v(normal_impulse + impulse, splat<V>(0));
    const V applied = accumulated - normal_impulse;
    put(c.normal_impulse, first, accumulated);
    put(c.max_normal_impulse, first, max_v(get<V>(c.max_normal_impulse, first), accumulated));
    const V pa = A.m * applied, pb = B.m * applied;
    A.vx -= pa * nx, A.vy -= pa * ny, A.vz -= pa * nz;
    B.vx += pb * nx, B.vy += pb * ny, B.vz += pb * nz;

    if constexpr (kMethod == PositionCorrection::SplitImpulse && kUseBias) {
      // Pseudo-velocities push penetrating bodies apart without adding momentum.
      ContactBlockExtra& e = s.extra[k];
      Vec3* pseudo = s.pseudo_velocity.data();
      const V target = min_v(-p.baumgarte * p.inverse_h * min_v(separation + p.slop, splat<V>(0)),
                             splat<V>(p.max_correction_speed));
      const V pvn = normal_difference(pseudo, ia, ib, nx, ny, nz);
      const V before = get<V>(e.pseudo_impulse, first);
      const V next = max_v(before - normal_mass * (pvn - target), splat<V>(0));
      const V pseudo_applied = next - before;
      put(e.pseudo_impulse, first, next);
      for (int l = 0; l < kWidth<V>; ++l) {
        const Vec3 n(nx[l], ny[l], nz[l]);
        pseudo[ia[l]] -= (A.m[l] * pseudo_applied[l]) * n;
        pseudo[ib[l]] += (B.m[l] * pseudo_applied[l]) * n;
      }
    }
  }
  scatter_motion<kSpin>(sb, ia, A);
  scatter_motion<kSpin>(sb, ib, B);
}

/// One pass over every block, W lanes at a time.
template <class V, ContactModel kModel, PositionCorrection kMethod, bool kUseBias, bool kTrackDelta>
[[gnu::always_inline]] inline void solve_blocks(SolverScratch& s, const PassParams& p) {
  const std::size_t count = s.blocks.size();
  for (std::size_t k = 0; k < count; ++k) {
    for (int first = 0; first < kLanes; first += kWidth<V>)
      solve_lanes<V, kModel, kMethod, kUseBias, kTrackDelta>(s, k, first, p);
  }
}

/// The baseline vector: half a block in float (one 16-byte register), a whole block in double.
using BaselineVector = std::conditional_t<kLanes == 8, Quad, Wide>;

/// The same pass compiled twice: for the baseline ISA and for AVX2. Every operation is IEEE
/// (no FMA contraction), so both give bit-identical results; only the register width differs.
/// flatten: GCC otherwise leaves small Eigen operators as calls in this hot loop.
template <ContactModel kModel, PositionCorrection kMethod, bool kUseBias, bool kTrackDelta>
[[gnu::flatten]] void solve_blocks_baseline(SolverScratch& s, const PassParams& p) {
  solve_blocks<BaselineVector, kModel, kMethod, kUseBias, kTrackDelta>(s, p);
}

#if RICOCHET_X86
template <ContactModel kModel, PositionCorrection kMethod, bool kUseBias, bool kTrackDelta>
[[gnu::flatten, gnu::target("avx2")]] void solve_blocks_avx2(SolverScratch& s,
                                                             const PassParams& p) {
  solve_blocks<Wide, kModel, kMethod, kUseBias, kTrackDelta>(s, p);
}
#endif

template <ContactModel kModel, PositionCorrection kMethod, bool kUseBias, bool kTrackDelta>
void solve_blocks_on_best_isa(SolverScratch& s, const PassParams& p) {
#if RICOCHET_X86
  if (s.wide) return solve_blocks_avx2<kModel, kMethod, kUseBias, kTrackDelta>(s, p);
#endif
  solve_blocks_baseline<kModel, kMethod, kUseBias, kTrackDelta>(s, p);
}

template <PositionCorrection kMethod, bool kUseBias, bool kTrackDelta>
void solve_blocks_for_model(SolverScratch& s, const PassParams& p) {
  switch (s.model) {
    case ContactModel::Normal:
      return solve_blocks_on_best_isa<ContactModel::Normal, kMethod, kUseBias, kTrackDelta>(s, p);
    case ContactModel::Friction:
      return solve_blocks_on_best_isa<ContactModel::Friction, kMethod, kUseBias, kTrackDelta>(s, p);
    case ContactModel::Spin:
      return solve_blocks_on_best_isa<ContactModel::Spin, kMethod, kUseBias, kTrackDelta>(s, p);
    case ContactModel::SpinRolling:
      return solve_blocks_on_best_isa<ContactModel::SpinRolling, kMethod, kUseBias, kTrackDelta>(s,
                                                                                                 p);
  }
}

/// Warm start of lanes first .. first + W of block k: last step's impulses applied again, lane by
/// lane as the scalar formulas (contacts of one block share no moving body, and unused lanes hold
/// zeros against the dummy, so a whole block at once gives the same bits as one lane at a time).
template <class V, bool kSpin, bool kRolling>
[[gnu::always_inline]] inline void warm_start_lanes(SolverScratch& s, std::size_t k, int first) {
  Motion* sb = s.bodies.data();
  const ContactBlock& c = s.blocks[k];
  const std::uint32_t* ia = c.a + first;
  const std::uint32_t* ib = c.b + first;
  BodyVectors<V> A = gather_motion<V, kSpin>(sb, ia), B = gather_motion<V, kSpin>(sb, ib);
  const V nx = get<V>(c.nx, first), ny = get<V>(c.ny, first), nz = get<V>(c.nz, first);
  const V fx = get<V>(c.fx, first), fy = get<V>(c.fy, first), fz = get<V>(c.fz, first);
  const V normal_impulse = get<V>(c.normal_impulse, first);
  // linear = n·normal_impulse + f
  const V lx = nx * normal_impulse + fx, ly = ny * normal_impulse + fy,
          lz = nz * normal_impulse + fz;
  A.vx = A.vx - A.m * lx, A.vy = A.vy - A.m * ly, A.vz = A.vz - A.m * lz;
  B.vx = B.vx + B.m * lx, B.vy = B.vy + B.m * ly, B.vz = B.vz + B.m * lz;
  if constexpr (kSpin) {
    V rx = splat<V>(0), ry = splat<V>(0), rz = splat<V>(0);
    if constexpr (kRolling) {
      const RollingBlock& r = s.rolling[k];
      rx = get<V>(r.x, first), ry = get<V>(r.y, first), rz = get<V>(r.z, first);
    }
    // torque_dir = n × f
    const V tx = ny * fz - nz * fy, ty = nz * fx - nx * fz, tz = nx * fy - ny * fx;
    const V ra = get<V>(c.ra, first), rb = get<V>(c.rb, first);
    A.wx = A.wx - A.i * (ra * tx + rx), A.wy = A.wy - A.i * (ra * ty + ry),
    A.wz = A.wz - A.i * (ra * tz + rz);
    B.wx = B.wx + B.i * (rx - rb * tx), B.wy = B.wy + B.i * (ry - rb * ty),
    B.wz = B.wz + B.i * (rz - rb * tz);
  }
  scatter_motion<kSpin>(sb, ia, A);
  scatter_motion<kSpin>(sb, ib, B);
}

template <class V, bool kSpin, bool kRolling>
[[gnu::always_inline]] inline void warm_start_blocks(SolverScratch& s) {
  for (std::size_t k = 0; k < s.blocks.size(); ++k) {
    for (int first = 0; first < kLanes; first += kWidth<V>)
      warm_start_lanes<V, kSpin, kRolling>(s, k, first);
  }
}

template <bool kSpin, bool kRolling>
[[gnu::flatten]] void warm_start_baseline(SolverScratch& s) {
  warm_start_blocks<BaselineVector, kSpin, kRolling>(s);
}

#if RICOCHET_X86
template <bool kSpin, bool kRolling>
[[gnu::flatten, gnu::target("avx2")]] void warm_start_avx2(SolverScratch& s) {
  warm_start_blocks<Wide, kSpin, kRolling>(s);
}
#endif

template <bool kSpin, bool kRolling>
void warm_start_on_best_isa(SolverScratch& s) {
#if RICOCHET_X86
  if (s.wide) return warm_start_avx2<kSpin, kRolling>(s);
#endif
  warm_start_baseline<kSpin, kRolling>(s);
}

template <PositionCorrection kMethod, bool kUseBias>
void solve_blocks_dispatch(SolverScratch& s, bool track_delta, const PassParams& p) {
  if (track_delta) {
    solve_blocks_for_model<kMethod, kUseBias, true>(s, p);
  } else {
    solve_blocks_for_model<kMethod, kUseBias, false>(s, p);
  }
}

}  // namespace

void WorldImpl::prepare_bodies() {
  SolverScratch& s = scratch.solver;
  const std::uint32_t awake = static_cast<std::uint32_t>(scratch.awake_list.size());
  const std::uint32_t dummy = awake;
  assign_reusing(s.index_of, state.bodies.slot_count(), dummy);
  s.bodies.resize(awake + 1);
  bool any_rolling = false;
  for (std::uint32_t k = 0; k < awake; ++k) {
    const std::uint32_t slot = scratch.awake_list[k];
    s.index_of[slot] = k;
    s.bodies[k] = state.bodies.motion[slot];
    any_rolling = any_rolling || state.bodies.material[slot].rolling_resistance > 0;
  }
  s.bodies[dummy] = Motion{};
  if (!def.enable_friction) {
    s.model = ContactModel::Normal;
  } else if (!def.enable_rotation) {
    s.model = ContactModel::Friction;
  } else {
    s.model = any_rolling && def.enable_rolling_resistance ? ContactModel::SpinRolling
                                                           : ContactModel::Spin;
  }
  s.has_rolling = s.model == ContactModel::SpinRolling;
  s.needs_shock = false;
#if RICOCHET_X86
  s.wide = def.wide_simd && __builtin_cpu_supports("avx2");
#endif
  assign_reusing(s.delta_position, awake + 1, Vec3::Zero());
  if (def.position_correction == PositionCorrection::SplitImpulse)
    assign_reusing(s.pseudo_velocity, awake + 1, Vec3::Zero());
}

void WorldImpl::prepare_contacts() {
  SolverScratch& s = scratch.solver;
  const std::uint32_t dummy = static_cast<std::uint32_t>(scratch.awake_list.size());
  const bool spin = def.enable_rotation && def.enable_friction;

  const std::size_t pair_count = state.pair_contacts.size();
  const std::size_t total = pair_count + state.static_contacts.size();
  color_contacts(s, state.pair_contacts, state.static_contacts);
  // Contact i of the pair contacts (kPair) or, from pair_count on, of the static contacts.
  const auto prepare = [&](auto pair, std::size_t i) {
    constexpr bool kPair = decltype(pair)::value;
    const Contact& c = kPair ? state.pair_contacts[i] : state.static_contacts[i - pair_count];
    const std::uint32_t block = s.lane_of_contact[i] / kLanes;
    const int lane = static_cast<int>(s.lane_of_contact[i] % kLanes);
    ContactBlock& blk = s.blocks[block];
    ContactBlockExtra& extra = s.extra[block];
    const std::uint32_t a = s.index_of[c.a];
    const std::uint32_t b = kPair ? s.index_of[c.b] : dummy;
    const Motion& A = s.bodies[a];
    const Motion& B = s.bodies[b];
    blk.a[lane] = a;
    blk.b[lane] = b;
    blk.nx[lane] = c.normal.x(), blk.ny[lane] = c.normal.y(), blk.nz[lane] = c.normal.z();
    blk.separation[lane] = c.separation;
    blk.ra[lane] = c.ra, blk.rb[lane] = c.rb;
    const Real mass_sum = A.inverse_mass + B.inverse_mass;
    // Inverse masses more than shock_mass_ratio apart: sequential impulses converge slowly.
    // (Static and kinematic sides have inverse mass 0 and never count.)
    const Real heavier = std::min(A.inverse_mass, B.inverse_mass);
    s.needs_shock = s.needs_shock || (heavier > 0 && heavier * def.shock_mass_ratio <
                                                         std::max(A.inverse_mass, B.inverse_mass));
    blk.normal_mass[lane] = mass_sum > 0 ? 1 / mass_sum : Real(0);
    const Real tangent_sum =
        spin ? mass_sum + A.inverse_inertia * c.ra * c.ra + B.inverse_inertia * c.rb * c.rb
             : mass_sum;
    blk.tangent_mass[lane] = tangent_sum > 0 ? 1 / tangent_sum : Real(0);
    blk.friction[lane] = c.friction;
    const Vec3 f = def.enable_friction
                       ? (c.friction_impulse - c.normal * c.normal.dot(c.friction_impulse)).eval()
                       : Vec3::Zero().eval();
    blk.normal_impulse[lane] = c.normal_impulse;
    blk.fx[lane] = f.x(), blk.fy[lane] = f.y(), blk.fz[lane] = f.z();
    blk.max_normal_impulse[lane] = 0;
    if (s.has_rolling) {
      RollingBlock& r = s.rolling[block];
      const Real rolling_sum = A.inverse_inertia + B.inverse_inertia;
      r.limit[lane] = c.rolling;
      r.mass[lane] = rolling_sum > 0 ? 1 / rolling_sum : Real(0);
      r.x[lane] = c.rolling_impulse.x(), r.y[lane] = c.rolling_impulse.y(),
      r.z[lane] = c.rolling_impulse.z();
    }
    extra.contact[lane] = static_cast<std::uint32_t>(i);
    extra.relative_velocity[lane] = c.normal.dot(B.linear_velocity - A.linear_velocity);
    extra.restitution[lane] = def.enable_restitution ? c.restitution : Real(0);
  };
  for (std::size_t i = 0; i < pair_count; ++i) prepare(std::true_type{}, i);
  for (std::size_t i = pair_count; i < total; ++i) prepare(std::false_type{}, i);
}

void WorldImpl::warm_start() {
  SolverScratch& s = scratch.solver;
  const bool spin = s.model == ContactModel::Spin || s.model == ContactModel::SpinRolling;
  if (!spin) return warm_start_on_best_isa<false, false>(s);
  if (s.has_rolling) return warm_start_on_best_isa<true, true>(s);
  warm_start_on_best_isa<true, false>(s);
}

void WorldImpl::reset_impulses() {
  SolverScratch& s = scratch.solver;
  for (ContactBlock& c : s.blocks) c.normal_impulse = c.fx = c.fy = c.fz = splat<Wide>(0);
  for (RollingBlock& r : s.rolling) r.x = r.y = r.z = splat<Wide>(0);
}

void WorldImpl::solve_contacts(Real h, bool use_bias) {
  PassParams p;
  p.inverse_h = 1 / h;
  p.slop = def.linear_slop;
  p.baumgarte = def.baumgarte;
  p.max_correction_speed = def.max_correction_speed;
  p.soft = make_softness(std::min(def.contact_hertz, Real(0.25) / h), def.contact_damping_ratio, h);
  const bool track_delta = def.substeps > 1;
  SolverScratch& s = scratch.solver;
  switch (def.position_correction) {  // only SoftStep has unbiased (relax) passes
    case PositionCorrection::Baumgarte:
      return solve_blocks_dispatch<PositionCorrection::Baumgarte, true>(s, track_delta, p);
    case PositionCorrection::SplitImpulse:
      return solve_blocks_dispatch<PositionCorrection::SplitImpulse, true>(s, track_delta, p);
    case PositionCorrection::SoftStep:
      if (use_bias)
        return solve_blocks_dispatch<PositionCorrection::SoftStep, true>(s, track_delta, p);
      return solve_blocks_dispatch<PositionCorrection::SoftStep, false>(s, track_delta, p);
  }
}

void WorldImpl::store_impulses() {
  SolverScratch& s = scratch.solver;
  const std::size_t pair_count = state.pair_contacts.size();
  for (std::size_t k = 0; k < s.blocks.size(); ++k) {
    const ContactBlock& c = s.blocks[k];
    const ContactBlockExtra& e = s.extra[k];
    for (int l = 0; l < kLanes; ++l) {
      const std::uint32_t i = e.contact[l];
      if (i == kUnusedLane) continue;
      Contact& contact =
          i < pair_count ? state.pair_contacts[i] : state.static_contacts[i - pair_count];
      contact.normal_impulse = c.normal_impulse[l];
      contact.friction_impulse = Vec3(c.fx[l], c.fy[l], c.fz[l]);
      if (s.has_rolling)
        contact.rolling_impulse = Vec3(s.rolling[k].x[l], s.rolling[k].y[l], s.rolling[k].z[l]);
      contact.max_normal_impulse = c.max_normal_impulse[l];
      contact.total_normal_impulse = e.total_normal_impulse[l];
      contact.relative_velocity = e.relative_velocity[l];
    }
  }
  for (std::size_t k = 0; k < scratch.awake_list.size(); ++k)
    state.bodies.motion[scratch.awake_list[k]] = scratch.solver.bodies[k];
}

void WorldImpl::solve(Real step_dt, ProfileTimer& timer) {
  const int substeps = def.substeps;
  const Real h = step_dt / static_cast<Real>(substeps);
  const bool explicit_euler = def.integrator == Integrator::ExplicitEuler;
  const bool relax = def.position_correction == PositionCorrection::SoftStep;
  const auto timed = [&](auto&& integrate) {
    timer.lap(profile.solve_ms);
    integrate();
    timer.lap(profile.integrate_ms);
  };
  convert_velocity_forms(h);
  prepare_bodies();
  prepare_contacts();
  const bool shock = def.shock_propagation && scratch.solver.needs_shock;
  if (shock) order_contacts_by_support();
  // Baumgarte corrects positions through velocity; the other methods have their own channel.
  const bool correction_in_shock_pass = def.position_correction == PositionCorrection::Baumgarte;
  if (!def.warm_starting) reset_impulses();
  for (int sub = 0; sub < substeps; ++sub) {
    // Explicit Euler takes a(x, v) from the substep's start, before anything moves.
    timed([&] { explicit_euler ? evaluate_accelerations() : integrate_velocities(h); });
    if (def.warm_starting) {
      warm_start();
    } else if (sub > 0) {
      reset_impulses();
    }
    for (int i = 0; i < def.iterations; ++i) solve_contacts(h, true);
    if (shock) propagate_shock(1 / h, correction_in_shock_pass);
    timed([&] { integrate_positions(h); });
    if (relax) {
      for (int i = 0; i < def.relax_iterations; ++i) solve_contacts(h, false);
    }
    if (explicit_euler) timed([&] { apply_accelerations(h); });
    for (std::size_t k = 0; k < scratch.solver.blocks.size(); ++k) {
      scratch.solver.extra[k].total_normal_impulse += scratch.solver.blocks[k].normal_impulse;
    }
  }
  apply_restitution(h);
  store_impulses();
  profile.wide_simd = scratch.solver.wide;
  timer.lap(profile.solve_ms);
}

}  // namespace ricochet::physics
