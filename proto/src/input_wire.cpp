/// The values of a client's Input (input_wire.h).

#include "ricochet/proto/input_wire.h"

#include <algorithm>
#include <cmath>

namespace ricochet::proto {

Stick stick_of(std::int32_t move_right, std::int32_t move_forward) {
  Stick stick{static_cast<float>(move_right) / kMoveSteps,
              static_cast<float>(move_forward) / kMoveSteps};
  const float length_sq = stick.right * stick.right + stick.forward * stick.forward;
  if (length_sq > 1) {
    const float length = std::sqrt(length_sq);
    stick.right /= length;
    stick.forward /= length;
  }
  return stick;
}

std::int32_t move_steps(float fraction) {
  return static_cast<std::int32_t>(std::lround(std::clamp(fraction, -1.0f, 1.0f) * kMoveSteps));
}

std::uint8_t to_view_fraction(double ticks_past) {
  const double steps = ticks_past * kViewFractionSteps;
  if (!(steps > 0)) return 0;  // negative or NaN
  return static_cast<std::uint8_t>(std::min(steps, double(kViewFractionSteps - 1)));
}

}  // namespace ricochet::proto
