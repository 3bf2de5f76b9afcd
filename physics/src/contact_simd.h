#pragma once
/// SIMD plumbing for the contact solver: the vector types a kernel pass works on, lane-wise
/// helpers, and the gather/scatter of body Motions into lane vectors (transposes). Included by
/// contact_solver.cpp only; everything here is always_inline (see below).

#include <cstdint>
#include <cstring>
#include <type_traits>

#include "contact_solver.h"

#if defined(__x86_64__) || defined(__i386__)
#define RICOCHET_X86 1
#else
#define RICOCHET_X86 0
#endif

namespace ricochet::physics::simd {

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

/// Integer lane indices for GCC's __builtin_shuffle on V.
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

/// Lane i of the result is lane I[i] of a:b (a's lanes first). GCC spells it with a mask vector,
/// Clang with constant arguments; a shuffle only moves bits, so both give the same results.
template <int... I, class V>
[[gnu::always_inline]] inline V shuffle(V a, V b) {
#if defined(__clang__)
  return __builtin_shufflevector(a, b, I...);
#else
  return __builtin_shuffle(a, b, typename ShuffleOf<V>::type{I...});
#endif
}

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
  const V t0 = shuffle<0, 4, 1, 5>(r[0], r[1]);
  const V t1 = shuffle<0, 4, 1, 5>(r[2], r[3]);
  const V t2 = shuffle<2, 6, 3, 7>(r[0], r[1]);
  const V t3 = shuffle<2, 6, 3, 7>(r[2], r[3]);
  r[0] = shuffle<0, 1, 4, 5>(t0, t1);
  r[1] = shuffle<2, 3, 6, 7>(t0, t1);
  r[2] = shuffle<0, 1, 4, 5>(t2, t3);
  r[3] = shuffle<2, 3, 6, 7>(t2, t3);
}

/// 8×8 transpose in three stages that map onto AVX's unpack, shuffle and 128-bit permute.
/// Its own inverse.
template <class V>
[[gnu::always_inline]] inline void transpose8(V* r) {
  V t[8], u[8];
  for (int k = 0; k < 8; k += 2) {  // interleave row pairs within each 128-bit half
    t[k] = shuffle<0, 8, 1, 9, 4, 12, 5, 13>(r[k], r[k + 1]);
    t[k + 1] = shuffle<2, 10, 3, 11, 6, 14, 7, 15>(r[k], r[k + 1]);
  }
  for (int k = 0; k < 8; k += 4) {  // pairs of pairs
    u[k] = shuffle<0, 1, 8, 9, 4, 5, 12, 13>(t[k], t[k + 2]);
    u[k + 1] = shuffle<2, 3, 10, 11, 6, 7, 14, 15>(t[k], t[k + 2]);
    u[k + 2] = shuffle<0, 1, 8, 9, 4, 5, 12, 13>(t[k + 1], t[k + 3]);
    u[k + 3] = shuffle<2, 3, 10, 11, 6, 7, 14, 15>(t[k + 1], t[k + 3]);
  }
  for (int k = 0; k < 4; ++k) {  // low halves give columns 0-3, high halves columns 4-7
    r[k] = shuffle<0, 1, 2, 3, 8, 9, 10, 11>(u[k], u[k + 4]);
    r[k + 4] = shuffle<4, 5, 6, 7, 12, 13, 14, 15>(u[k], u[k + 4]);
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
    const V t0 = shuffle<0, 8, 1, 9, 4, 12, 5, 13>(r[0], r[1]);
    const V t1 = shuffle<2, 10, 3, 11, 6, 14, 7, 15>(r[0], r[1]);
    const V t2 = shuffle<0, 8, 1, 9, 4, 12, 5, 13>(r[2], r[3]);
    const V t3 = shuffle<2, 10, 3, 11, 6, 14, 7, 15>(r[2], r[3]);
    r[0] = shuffle<0, 1, 8, 9, 4, 5, 12, 13>(t0, t2);
    r[1] = shuffle<2, 3, 10, 11, 6, 7, 14, 15>(t0, t2);
    r[2] = shuffle<0, 1, 8, 9, 4, 5, 12, 13>(t1, t3);
    r[3] = shuffle<2, 3, 10, 11, 6, 7, 14, 15>(t1, t3);
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

}  // namespace ricochet::physics::simd
