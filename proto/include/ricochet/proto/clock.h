#pragma once
/// Time in proto/ is a parameter: every endpoint call takes `now` in microseconds on a clock the
/// caller chooses and never reads a clock itself. The server passes its steady clock, tests pass
/// fake time. A connect token's expiry is on the issuing server's clock (the same process makes
/// and checks tokens), so clients never compare it with their own.

#include <cstdint>

namespace ricochet::proto {

using TimeUs = std::int64_t;  ///< microseconds on the caller's monotonic clock

inline constexpr TimeUs kMicrosPerSecond = 1'000'000;
inline constexpr TimeUs kMicrosPerMilli = 1'000;

}  // namespace ricochet::proto
