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
#include <bit>
#include <cmath>
#include <cstring>
#include <numbers>
#include <type_traits>

#include "math_util.h"
#include "world_impl.h"

namespace ricochet::physics {

namespace {

#if defined(__x86_64__) || defined(__i386__)
#define RICOCHET_X86 1
#else
#define RICOCHET_X86 0
#endif

constexpr int kColors = 24;
constexpr std::uint32_t kUnusedLane = ~0u;

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
// Every function that takes or returns a vector is always_inline: the AVX2 kernel must never call
// a baseline-ISA function with a 32-byte vector argument (the two pass it differently), and at
// -O0 nothing else inlines.
//
// Vectors. A kernel pass works on V, either a whole block (Wide: one AVX register) or, on the
// baseline float path, half a block at a time (Quad: four floats, one SSE2/NEON register).
// Contacts of one block share no moving body, so solving its halves one after the other gives
// the same bits as solving it whole.

using Quad = Real __attribute__((vector_size(4 * sizeof(Real))));
/// A whole block's lanes as a computation type (Lanes is the storage type: the same vector,
/// aligned for the AVX2 path, but an attribute a template argument cannot carry).
using Wide = Real __attribute__((vector_size(sizeof(Lanes))));

template <class V>
constexpr int kWidth = static_cast<int>(sizeof(V) / sizeof(Real));

/// Integer lane indices for __builtin_shuffle on V.
using IndexReal = std::conditional_t<sizeof(Real) == 4, std::int32_t, std::int64_t>;
template <class V>
struct ShuffleOf;
template <>
struct ShuffleOf<Wide> {
  using type = IndexReal __attribute__((vector_size(sizeof(Wide))));
};
#if !defined(RICOCHET_DOUBLE)
template <>
struct ShuffleOf<Quad> {
  using type = IndexReal __attribute__((vector_size(sizeof(Quad))));
};
#endif

template <class V>
[[gnu::always_inline]] inline V splat(Real x) {
  return V{} + x;
}
template <class V>
[[gnu::always_inline]] inline V max_v(V a, V b) {
  return a > b ? a : b;
}
template <class V>
[[gnu::always_inline]] inline V min_v(V a, V b) {
  return a < b ? a : b;
}
template <class V>
[[gnu::always_inline]] inline V sqrt_v(V x) {
  V r;
  for (int l = 0; l < kWidth<V>; ++l) r[l] = std::sqrt(x[l]);  // vectorised: sqrtps
  return r;
}

/// Factor that brings a vector of squared length len2 inside a circle of radius limit (>= 0).
template <class V>
[[gnu::always_inline]] inline V circle_clamp_scale(V len2, V limit) {
  const auto outside = len2 > limit * limit;  // implies len2 > 0
  const V safe_len2 = outside ? len2 : splat<V>(1);
  return outside ? limit / sqrt_v(safe_len2) : splat<V>(1);
}

template <class V>
[[gnu::always_inline]] inline V load(const Real* p) {
  V v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
template <class V>
[[gnu::always_inline]] inline void store(Real* p, V v) {
  std::memcpy(p, &v, sizeof v);
}

/// Lanes first .. first + width of a block field.
template <class V>
[[gnu::always_inline]] inline V get(const Lanes& field, int first) {
  return load<V>(reinterpret_cast<const Real*>(&field) + first);
}
template <class V>
[[gnu::always_inline]] inline void put(Lanes& field, int first, V v) {
  store(reinterpret_cast<Real*>(&field) + first, v);
}

// ---------------------------------------------------------------------------------------------
// Gather and scatter: a Motion is eight Reals (v, 1/m, w, 1/I); W bodies' Motions are transposed
// into eight vectors of W lanes and back.

static_assert(sizeof(Motion) == 8 * sizeof(Real), "Motion must be v|m|w|i");

template <class V>
struct BodyVectors {
  V vx, vy, vz, m, wx, wy, wz, i;
};

/// 4×4 transpose. Its own inverse.
template <class V>
[[gnu::always_inline]] inline void transpose4(V* r) {
  using S = typename ShuffleOf<V>::type;
  const V t0 = __builtin_shuffle(r[0], r[1], S{0, 4, 1, 5});
  const V t1 = __builtin_shuffle(r[2], r[3], S{0, 4, 1, 5});
  const V t2 = __builtin_shuffle(r[0], r[1], S{2, 6, 3, 7});
  const V t3 = __builtin_shuffle(r[2], r[3], S{2, 6, 3, 7});
  r[0] = __builtin_shuffle(t0, t1, S{0, 1, 4, 5});
  r[1] = __builtin_shuffle(t0, t1, S{2, 3, 6, 7});
  r[2] = __builtin_shuffle(t2, t3, S{0, 1, 4, 5});
  r[3] = __builtin_shuffle(t2, t3, S{2, 3, 6, 7});
}

/// 8×8 transpose in three stages that map onto AVX's unpack, shuffle and 128-bit permute.
/// Its own inverse.
template <class V>
[[gnu::always_inline]] inline void transpose8(V* r) {
  using S = typename ShuffleOf<V>::type;
  V t[8], u[8];
  for (int k = 0; k < 8; k += 2) {  // interleave row scratch.pairs within each 128-bit half
    t[k] = __builtin_shuffle(r[k], r[k + 1], S{0, 8, 1, 9, 4, 12, 5, 13});
    t[k + 1] = __builtin_shuffle(r[k], r[k + 1], S{2, 10, 3, 11, 6, 14, 7, 15});
  }
  for (int k = 0; k < 8; k += 4) {  // scratch.pairs of scratch.pairs
    u[k] = __builtin_shuffle(t[k], t[k + 2], S{0, 1, 8, 9, 4, 5, 12, 13});
    u[k + 1] = __builtin_shuffle(t[k], t[k + 2], S{2, 3, 10, 11, 6, 7, 14, 15});
    u[k + 2] = __builtin_shuffle(t[k + 1], t[k + 3], S{0, 1, 8, 9, 4, 5, 12, 13});
    u[k + 3] = __builtin_shuffle(t[k + 1], t[k + 3], S{2, 3, 10, 11, 6, 7, 14, 15});
  }
  for (int k = 0; k < 4; ++k) {  // low halves give columns 0-3, high halves columns 4-7
    r[k] = __builtin_shuffle(u[k], u[k + 4], S{0, 1, 2, 3, 8, 9, 10, 11});
    r[k + 4] = __builtin_shuffle(u[k], u[k + 4], S{4, 5, 6, 7, 12, 13, 14, 15});
  }
}

/// Rows in, lanes out (and back). Eight-wide: rows are bodies, one 8×8 transpose. Four-wide:
/// rows 0-3 are the bodies' v|m halves and rows 4-7 their w|i halves, two 4×4 transposes.
template <class V>
[[gnu::always_inline]] inline void transpose_motions(V* r) {
  if constexpr (kWidth<V> == 8) {
    transpose8(r);
  } else {
    static_assert(kWidth<V> == 4);
    transpose4(r);
    transpose4(r + 4);
  }
}

template <class V>
[[gnu::always_inline]] inline BodyVectors<V> gather(const Motion* bodies,
                                                    const std::uint32_t* index) {
  constexpr int W = kWidth<V>;
  V r[8];
  for (int l = 0; l < W; ++l) {
    const Real* motion = bodies[index[l]].linear_velocity.data();
    for (int part = 0; part < 8 / W; ++part) r[l + part * W] = load<V>(motion + part * W);
  }
  transpose_motions(r);
  return {r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7]};
}

/// Writes velocities back (the inverse masses ride along unchanged).
template <class V>
[[gnu::always_inline]] inline void scatter(Motion* bodies, const std::uint32_t* index,
                                           const BodyVectors<V>& b) {
  constexpr int W = kWidth<V>;
  V r[8] = {b.vx, b.vy, b.vz, b.m, b.wx, b.wy, b.wz, b.i};
  transpose_motions(r);
  for (int l = 0; l < W; ++l) {
    Real* motion = bodies[index[l]].linear_velocity.data();
    for (int part = 0; part < 8 / W; ++part) store(motion + part * W, r[l + part * W]);
  }
}

/// Linear part only (v, 1/m): for contact models without spin, half the memory traffic.
/// Eight-wide: body k in the low half and body k + 4 in the high half of row k, then a 4×4
/// transpose within each half (the first two stages of transpose8).
template <class V>
[[gnu::always_inline]] inline void transpose_linear(V* r) {
  if constexpr (kWidth<V> == 8) {
    using S = typename ShuffleOf<V>::type;
    const V t0 = __builtin_shuffle(r[0], r[1], S{0, 8, 1, 9, 4, 12, 5, 13});
    const V t1 = __builtin_shuffle(r[0], r[1], S{2, 10, 3, 11, 6, 14, 7, 15});
    const V t2 = __builtin_shuffle(r[2], r[3], S{0, 8, 1, 9, 4, 12, 5, 13});
    const V t3 = __builtin_shuffle(r[2], r[3], S{2, 10, 3, 11, 6, 14, 7, 15});
    r[0] = __builtin_shuffle(t0, t2, S{0, 1, 8, 9, 4, 5, 12, 13});
    r[1] = __builtin_shuffle(t0, t2, S{2, 3, 10, 11, 6, 7, 14, 15});
    r[2] = __builtin_shuffle(t1, t3, S{0, 1, 8, 9, 4, 5, 12, 13});
    r[3] = __builtin_shuffle(t1, t3, S{2, 3, 10, 11, 6, 7, 14, 15});
  } else {
    transpose4(r);
  }
}

template <class V>
[[gnu::always_inline]] inline BodyVectors<V> gather_linear(const Motion* bodies,
                                                           const std::uint32_t* index) {
  V r[4];
  for (int k = 0; k < 4; ++k) {
    const Real* low = bodies[index[k]].linear_velocity.data();
    if constexpr (kWidth<V> == 8) {
      const Real* high = bodies[index[k + 4]].linear_velocity.data();
      r[k] = __builtin_shufflevector(load<Quad>(low), load<Quad>(high), 0, 1, 2, 3, 4, 5, 6, 7);
    } else {
      r[k] = load<V>(low);
    }
  }
  transpose_linear(r);
  return {r[0], r[1], r[2], r[3], V{}, V{}, V{}, V{}};
}

template <class V>
[[gnu::always_inline]] inline void scatter_linear(Motion* bodies, const std::uint32_t* index,
                                                  const BodyVectors<V>& b) {
  V r[4] = {b.vx, b.vy, b.vz, b.m};
  transpose_linear(r);
  for (int k = 0; k < 4; ++k) {
    Real* low = bodies[index[k]].linear_velocity.data();
    if constexpr (kWidth<V> == 8) {
      store(low, __builtin_shufflevector(r[k], r[k], 0, 1, 2, 3));
      store(bodies[index[k + 4]].linear_velocity.data(),
            __builtin_shufflevector(r[k], r[k], 4, 5, 6, 7));
    } else {
      store(low, r[k]);
    }
  }
}

/// Normal component of a per-body vector difference (b - a), lane-wise.
template <class V>
[[gnu::always_inline]] inline V normal_difference(const Vec3* v, const std::uint32_t* a,
                                                  const std::uint32_t* b, V nx, V ny, V nz) {
  V d;
  for (int l = 0; l < kWidth<V>; ++l) {
    const Vec3 diff = v[b[l]] - v[a[l]];
    d[l] = diff.x() * nx[l] + diff.y() * ny[l] + diff.z() * nz[l];
  }
  return d;
}

// ---------------------------------------------------------------------------------------------
// The kernel.

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
  BodyVectors<V> A, B;
  if constexpr (kSpin) {
    A = gather<V>(sb, ia);
    B = gather<V>(sb, ib);
  } else {
    A = gather_linear<V>(sb, ia);
    B = gather_linear<V>(sb, ib);
  }
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
  if constexpr (kSpin) {
    scatter(sb, ia, A);
    scatter(sb, ib, B);
  } else {
    scatter_linear(sb, ia, A);
    scatter_linear(sb, ib, B);
  }
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
  s.index_of.assign(state.bodies.slot_count(), dummy);
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
  s.delta_position.assign(awake + 1, Vec3::Zero());
  if (def.position_correction == PositionCorrection::SplitImpulse)
    s.pseudo_velocity.assign(awake + 1, Vec3::Zero());
}

void WorldImpl::prepare_contacts() {
  SolverScratch& s = scratch.solver;
  const std::uint32_t awake = static_cast<std::uint32_t>(scratch.awake_list.size());
  const std::uint32_t dummy = awake;
  const bool spin = def.enable_rotation && def.enable_friction;

  // Greedy colouring: a contact takes the first colour where neither of its moving bodies is used.
  const std::size_t pair_count = state.pair_contacts.size();
  const std::size_t total = pair_count + state.static_contacts.size();
  const auto contact_at = [&](std::size_t i) -> Contact& {
    return i < pair_count ? state.pair_contacts[i] : state.static_contacts[i - pair_count];
  };
  // used_colors[k]: bit c set when body k already has a contact of colour c (the dummy never does).
  std::vector<std::uint32_t>& used_colors = s.used_colors;
  used_colors.assign(awake + 1, 0);
  s.color_of.resize(total);
  std::vector<std::uint32_t> color_count(kColors + 1, 0);
  for (std::size_t i = 0; i < total; ++i) {
    const Contact& c = contact_at(i);
    const std::uint32_t a = s.index_of[c.a];
    const std::uint32_t b = i < pair_count ? s.index_of[c.b] : dummy;
    const std::uint32_t free_colors = ~(used_colors[a] | used_colors[b]) & ((1u << kColors) - 1);
    const std::uint32_t color =
        free_colors != 0 ? static_cast<std::uint32_t>(std::countr_zero(free_colors)) : kColors;
    if (color < kColors) {
      if (a != dummy) used_colors[a] |= 1u << color;
      if (b != dummy) used_colors[b] |= 1u << color;
    }
    s.color_of[i] = color;
    ++color_count[color];
  }
  std::size_t block_count = total > 0 ? color_count[kColors] : 0;
  for (int k = 0; k < kColors; ++k) block_count += (color_count[k] + kLanes - 1) / kLanes;
  s.blocks.assign(block_count, ContactBlock{});
  s.extra.assign(block_count, ContactBlockExtra{});
  s.lane_of_contact.resize(total);
  s.rolling.assign(s.has_rolling ? block_count : 0, RollingBlock{});

  // Block ranges per colour; overflow contacts get a block each.
  std::vector<std::uint32_t> next_block(kColors + 1), next_lane(kColors + 1, 0);
  std::uint32_t first = 0;
  for (int k = 0; k <= kColors; ++k) {
    next_block[k] = first;
    first += k < kColors ? (color_count[k] + kLanes - 1) / kLanes : color_count[k];
  }
  for (std::size_t b = 0; b < block_count; ++b) {
    for (int l = 0; l < kLanes; ++l) {
      s.blocks[b].a[l] = s.blocks[b].b[l] = dummy;
      s.extra[b].contact[l] = kUnusedLane;
    }
  }
  for (std::size_t i = 0; i < total; ++i) {
    Contact& c = contact_at(i);
    const std::uint32_t color = s.color_of[i];
    const std::uint32_t block = next_block[color];
    const int lane = static_cast<int>(next_lane[color]);
    if (color == kColors || lane + 1 == kLanes) {
      ++next_block[color];
      next_lane[color] = 0;
    } else {
      ++next_lane[color];
    }
    ContactBlock& blk = s.blocks[block];
    ContactBlockExtra& extra = s.extra[block];
    const std::uint32_t a = s.index_of[c.a];
    const std::uint32_t b = i < pair_count ? s.index_of[c.b] : dummy;
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
    s.lane_of_contact[i] = block * kLanes + static_cast<std::uint32_t>(lane);
    extra.relative_velocity[lane] = c.normal.dot(B.linear_velocity - A.linear_velocity);
    extra.restitution[lane] = def.enable_restitution ? c.restitution : Real(0);
  }
}

void WorldImpl::warm_start() {
  SolverScratch& s = scratch.solver;
  const bool spin = s.model == ContactModel::Spin || s.model == ContactModel::SpinRolling;
  for (std::size_t k = 0; k < s.blocks.size(); ++k) {
    const ContactBlock& c = s.blocks[k];
    for (int l = 0; l < kLanes; ++l) {
      if (s.extra[k].contact[l] == kUnusedLane) continue;
      const Vec3 n(c.nx[l], c.ny[l], c.nz[l]);
      const Vec3 f(c.fx[l], c.fy[l], c.fz[l]);
      const Vec3 rolling = s.has_rolling
                               ? Vec3(s.rolling[k].x[l], s.rolling[k].y[l], s.rolling[k].z[l])
                               : Vec3::Zero().eval();
      const Vec3 linear = n * c.normal_impulse[l] + f;
      const Vec3 torque_dir = n.cross(f);
      Motion& A = s.bodies[c.a[l]];
      Motion& B = s.bodies[c.b[l]];
      A.linear_velocity -= A.inverse_mass * linear;
      B.linear_velocity += B.inverse_mass * linear;
      if (spin) {
        A.angular_velocity -= A.inverse_inertia * (c.ra[l] * torque_dir + rolling);
        B.angular_velocity += B.inverse_inertia * (rolling - c.rb[l] * torque_dir);
      }
    }
  }
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

/// Restitution that keeps energy across the impact's phase inside the step. The stored velocity
/// of a semi-implicit body is the mean over the step it just took, ½·a·h off its true value, and
/// the impact happens somewhere inside the step; reflecting the stored approach speed loses up to
/// 2·a·h per bounce. Per contact with relative normal velocity v, relative normal acceleration a
/// (constant over the step), gap d at prepare and d' at the end:
///   true approach at the step start  w  = v + s·½·a·h   (s = +1 semi-implicit, -1 explicit)
///   approach at the moment of touch  wc = -√(w² - 2·a·d)            (constant-acceleration fall)
///   departure at the touch           wo = e·|wc|, and at the end √(wo² + 2·a·d')
///   stored departure velocity        v' = √(wo² + 2·a·d') - s·½·a·h
/// so ½·w² + a·gap, which semi-implicit Euler conserves exactly under constant acceleration, is
/// scaled by e² and nothing else.
void WorldImpl::apply_restitution(Real h) {
  if (!def.enable_restitution) return;
  SolverScratch& s = scratch.solver;
  const Real threshold = def.restitution_threshold;
  const Real half_h = (def.integrator == Integrator::ExplicitEuler ? Real(-0.5) : Real(0.5)) * h;
  const auto acceleration = [&](std::uint32_t body) -> Vec3 {
    return body < s.acceleration.size() ? s.acceleration[body] : Vec3::Zero().eval();
  };
  for (std::size_t k = 0; k < s.blocks.size(); ++k) {
    ContactBlock& c = s.blocks[k];
    ContactBlockExtra& e = s.extra[k];
    for (int l = 0; l < kLanes; ++l) {
      if (e.contact[l] == kUnusedLane || e.restitution[l] == 0 ||
          e.relative_velocity[l] > -threshold || c.max_normal_impulse[l] == 0) {
        continue;
      }
      const Vec3 n(c.nx[l], c.ny[l], c.nz[l]);
      Motion& A = s.bodies[c.a[l]];
      Motion& B = s.bodies[c.b[l]];
      const Real a = n.dot(acceleration(c.b[l]) - acceleration(c.a[l]));
      const Real w = e.relative_velocity[l] + half_h * a;
      const Real gap = std::max(c.separation[l], Real(0));
      const Real touch = std::sqrt(std::max(w * w - 2 * a * gap, Real(0)));
      const Real end_gap = std::max(
          c.separation[l] + n.dot(s.delta_position[c.b[l]] - s.delta_position[c.a[l]]), Real(0));
      const Real departure = e.restitution[l] * touch;
      const Real target =
          std::sqrt(std::max(departure * departure + 2 * a * end_gap, Real(0))) - half_h * a;
      const Real vn = n.dot(B.linear_velocity - A.linear_velocity);
      const Real impulse = c.normal_mass[l] * (target - vn);
      const Real accumulated = std::max(c.normal_impulse[l] + impulse, Real(0));
      const Real applied = accumulated - c.normal_impulse[l];
      c.normal_impulse[l] = accumulated;
      c.max_normal_impulse[l] = std::max(c.max_normal_impulse[l], accumulated);
      e.total_normal_impulse[l] += applied;
      A.linear_velocity -= (A.inverse_mass * applied) * n;
      B.linear_velocity += (B.inverse_mass * applied) * n;
    }
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
