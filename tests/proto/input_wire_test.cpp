// The values of a client's Input: the stick a pair of move steps stands for, move steps from a
// fraction, and the 1/256-tick view fraction both ways.

#include "ricochet/proto/input_wire.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace ricochet::proto::input_wire_test {
namespace {

TEST(InputWire, MoveStepsAreAFractionOfFullInput) {
  EXPECT_EQ(stick_of(0, 0), (Stick{0, 0}));
  EXPECT_EQ(stick_of(kMoveSteps, 0), (Stick{1, 0}));
  EXPECT_EQ(stick_of(0, -kMoveSteps), (Stick{0, -1}));
  const Stick half = stick_of(-64, 32);
  EXPECT_FLOAT_EQ(half.right, -64.0f / 127);
  EXPECT_FLOAT_EQ(half.forward, 32.0f / 127);
}

TEST(InputWire, AFullDiagonalIsShortenedToUnitLength) {
  const Stick diagonal = stick_of(kMoveSteps, kMoveSteps);
  EXPECT_NEAR(std::hypot(diagonal.right, diagonal.forward), 1.0f, 1e-6f);
  EXPECT_FLOAT_EQ(diagonal.right, diagonal.forward);
  // Exactly the single-precision steps the server moves by: k/127, then divided by the length.
  const float right = 100.0f / 127, forward = -90.0f / 127;
  const float length = std::sqrt(right * right + forward * forward);
  EXPECT_EQ(stick_of(100, -90), (Stick{right / length, forward / length}));
  // A vector of length <= 1 is kept as it is.
  EXPECT_EQ(stick_of(89, 89), (Stick{89.0f / 127, 89.0f / 127}));
}

TEST(InputWire, MoveStepsRoundAndClampAFraction) {
  EXPECT_EQ(move_steps(0), 0);
  EXPECT_EQ(move_steps(1), kMoveSteps);
  EXPECT_EQ(move_steps(-1), -kMoveSteps);
  EXPECT_EQ(move_steps(2.5f), kMoveSteps);
  EXPECT_EQ(move_steps(-7), -kMoveSteps);
  EXPECT_EQ(move_steps(0.5f), 64);  // 63.5 rounds away from zero
  EXPECT_EQ(move_steps(-0.1f), -13);
  for (std::int32_t steps = -kMoveSteps; steps <= kMoveSteps; ++steps) {
    EXPECT_EQ(move_steps(static_cast<float>(steps) / kMoveSteps), steps) << steps;
  }
}

TEST(InputWire, AViewFractionCountsTwoHundredFiftySixthsOfATick) {
  EXPECT_EQ(view_fraction_ticks(0), 0.0);
  EXPECT_EQ(view_fraction_ticks(128), 0.5);
  EXPECT_EQ(view_fraction_ticks(255), 255.0 / 256);
  EXPECT_EQ(to_view_fraction(0), 0);
  EXPECT_EQ(to_view_fraction(0.5), 128);
  EXPECT_EQ(to_view_fraction(0.999), 255);  // rounded down
  EXPECT_EQ(to_view_fraction(1.0), 255);    // never a whole tick
  EXPECT_EQ(to_view_fraction(7.0), 255);
  EXPECT_EQ(to_view_fraction(-0.25), 0);
  EXPECT_EQ(to_view_fraction(std::numeric_limits<double>::quiet_NaN()), 0);
  for (int fraction = 0; fraction < 256; ++fraction) {
    const auto wire = static_cast<std::uint8_t>(fraction);
    EXPECT_EQ(to_view_fraction(view_fraction_ticks(wire)), wire) << fraction;
  }
}

TEST(InputWire, ButtonsAreTheLowThreeBits) {
  EXPECT_EQ(kKnownButtons, 0b111u);
  EXPECT_EQ(kButtonJump | kButtonFire | kButtonAltFire, kKnownButtons);
  EXPECT_EQ(kButtonJump & kButtonFire, 0u);
}

}  // namespace
}  // namespace ricochet::proto::input_wire_test
