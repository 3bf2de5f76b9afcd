#pragma once
/// Clang lacks GCC's __builtin_shuffle(a, b, mask), which the contact solver (physics/src) uses for
/// its lane transposes (clang's __builtin_shufflevector wants the indices as constant arguments,
/// not as a mask vector). The fuzz build force-includes this header into the physics sources and
/// supplies the same operation lane by lane: lane i of the result is lane mask[i] of a:b. A
/// shuffle only moves bits, so results stay bit-identical.
///
/// The mask is passed as S{0, 4, 1, 5}, which the preprocessor splits at its commas; the variadic
/// macro glues it back together.

template <class V, class Mask>
[[gnu::always_inline]] inline V ricochet_fuzz_shuffle(V a, V b, Mask mask) {
  constexpr int kLanes = static_cast<int>(sizeof(V) / sizeof(a[0]));
  V out;
  for (int i = 0; i < kLanes; ++i) {
    const int k = static_cast<int>(mask[i]);
    out[i] = k < kLanes ? a[k] : b[k - kLanes];
  }
  return out;
}

#define __builtin_shuffle(a, b, ...) ricochet_fuzz_shuffle(a, b, __VA_ARGS__)
