#pragma once
/// The time budget of an end-to-end test. Every wait is bounded in real time, and a test's
/// bounds added up stay a margin under the limit ctest gives it (RICOCHET_CTEST_TIMEOUT_S, set in
/// CMakeLists.txt beside the TIMEOUT), checked at compile time (`static_assert(fits_ctest(...))`):
/// a slow run fails on its own assertion, with the server's log, instead of being killed.

#include <chrono>

namespace ricochet::test {

/// ctest's limit for each test of this binary.
inline constexpr std::chrono::seconds kCtestTimeout{RICOCHET_CTEST_TIMEOUT_S};

/// Whether a test whose bounded waits add up to `waits` ends `margin` before ctest's limit.
constexpr bool fits_ctest(std::chrono::seconds waits,
                          std::chrono::seconds margin = std::chrono::seconds{6}) {
  return waits + margin <= kCtestTimeout;
}

}  // namespace ricochet::test
