#pragma once
/// What a libFuzzer target asserts: a broken property aborts, which libFuzzer reports as a crash
/// with the input that broke it (assert() would vanish in Release).

#include <cstdlib>

namespace ricochet::fuzz {

inline void check(bool condition) {
  if (!condition) std::abort();
}

}  // namespace ricochet::fuzz
