// Validation of untrusted inputs and the per-client jitter buffer.

#include "ricochet/server/input_buffer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

namespace ricochet::server::input_buffer_test {
namespace {

wire::Input wire_input(std::uint32_t sequence) {
  wire::Input in;
  in.set_sequence(sequence);
  in.set_move_forward(127);
  in.set_yaw(0.5f);
  in.set_pitch(-0.25f);
  in.set_buttons(proto::kButtonJump | proto::kButtonFire);
  in.set_weapon_slot(2);
  return in;
}

PlayerInput input(std::uint32_t sequence) {
  PlayerInput in;
  in.sequence = sequence;
  in.move_forward = 1;
  return in;
}

std::uint64_t count(const InputDropCounters& drops, InputDrop reason) {
  return drops[static_cast<std::size_t>(reason)];
}

TEST(ValidateInput, DequantisesAValidInput) {
  PlayerInput out;
  InputDrop reason{};
  ASSERT_TRUE(validate_input(wire_input(7), out, reason));
  EXPECT_EQ(out.sequence, 7u);
  EXPECT_FLOAT_EQ(out.move_forward, 1);
  EXPECT_FLOAT_EQ(out.move_right, 0);
  EXPECT_FLOAT_EQ(out.yaw_rad, 0.5f);
  EXPECT_FLOAT_EQ(out.pitch_rad, -0.25f);
  EXPECT_TRUE(out.pressed(proto::kButtonJump));
  EXPECT_TRUE(out.pressed(proto::kButtonFire));
  EXPECT_FALSE(out.pressed(proto::kButtonAltFire));
  EXPECT_EQ(out.weapon_slot, 2u);
}

TEST(ValidateInput, ShortensADiagonalToUnitLength) {
  wire::Input in = wire_input(1);
  in.set_move_right(-127);
  PlayerInput out;
  InputDrop reason{};
  ASSERT_TRUE(validate_input(in, out, reason));
  EXPECT_NEAR(std::hypot(out.move_right, out.move_forward), 1.0, 1e-6);
  EXPECT_NEAR(out.move_right, -std::sqrt(0.5), 1e-6);
}

TEST(ValidateInput, RefusesNonFiniteAngles) {
  const float values[] = {std::numeric_limits<float>::quiet_NaN(),
                          std::numeric_limits<float>::infinity(),
                          -std::numeric_limits<float>::infinity()};
  for (const float bad : values) {
    for (int field = 0; field < 2; ++field) {
      wire::Input in = wire_input(1);
      if (field == 0)
        in.set_yaw(bad);
      else
        in.set_pitch(bad);
      PlayerInput out;
      InputDrop reason{};
      EXPECT_FALSE(validate_input(in, out, reason));
      EXPECT_EQ(reason, InputDrop::NonFinite);
    }
  }
}

TEST(ValidateInput, RefusesOutOfRangeValues) {
  const auto refused = [](void (*spoil)(wire::Input&)) {
    wire::Input in = wire_input(1);
    spoil(in);
    PlayerInput out;
    InputDrop reason{};
    return !validate_input(in, out, reason) && reason == InputDrop::OutOfRange;
  };
  EXPECT_TRUE(refused([](wire::Input& in) { in.set_move_right(128); }));
  EXPECT_TRUE(refused([](wire::Input& in) { in.set_move_forward(-128); }));
  EXPECT_TRUE(
      refused([](wire::Input& in) { in.set_move_forward(std::numeric_limits<int>::min()); }));
  EXPECT_TRUE(refused([](wire::Input& in) { in.set_yaw(7); }));
  EXPECT_TRUE(refused([](wire::Input& in) { in.set_pitch(1.6f); }));
  EXPECT_TRUE(refused([](wire::Input& in) { in.set_buttons(1u << 3); }));
  EXPECT_TRUE(refused([](wire::Input& in) { in.set_weapon_slot(10); }));
  // The edges are accepted.
  wire::Input edge = wire_input(1);
  edge.set_move_right(-127);
  edge.set_yaw(-2 * std::numbers::pi_v<float>);
  edge.set_pitch(std::numbers::pi_v<float> / 2);
  edge.set_weapon_slot(9);
  PlayerInput out;
  InputDrop reason{};
  EXPECT_TRUE(validate_input(edge, out, reason));
}

TEST(ValidateInput, RefusesSequenceZero) {
  PlayerInput out;
  InputDrop reason{};
  EXPECT_FALSE(validate_input(wire_input(0), out, reason));
  EXPECT_EQ(reason, InputDrop::ZeroSequence);
}

TEST(InputBuffer, AppliesOneInputPerTickInSequenceOrder) {
  InputBuffer buffer;
  InputDropCounters drops{};
  buffer.offer(input(3), drops);
  buffer.offer(input(1), drops);
  buffer.offer(input(2), drops);
  bool repeated = true;
  for (std::uint32_t expected = 1; expected <= 3; ++expected) {
    EXPECT_EQ(buffer.next(repeated).sequence, expected);
    EXPECT_FALSE(repeated);
    EXPECT_EQ(buffer.last_applied_sequence(), expected);
  }
  EXPECT_EQ(drops, InputDropCounters{});
}

TEST(InputBuffer, RepeatsTheLastInputWhenNoneArrived) {
  InputBuffer buffer;
  InputDropCounters drops{};
  bool repeated = false;
  EXPECT_EQ(buffer.next(repeated).sequence, 0u);  // nothing yet: the neutral input
  EXPECT_TRUE(repeated);
  EXPECT_FLOAT_EQ(buffer.next(repeated).move_forward, 0);
  buffer.offer(input(1), drops);
  EXPECT_EQ(buffer.next(repeated).sequence, 1u);
  EXPECT_FALSE(repeated);
  const PlayerInput& again = buffer.next(repeated);
  EXPECT_TRUE(repeated);
  EXPECT_EQ(again.sequence, 1u);
  EXPECT_FLOAT_EQ(again.move_forward, 1);
  EXPECT_EQ(buffer.last_applied_sequence(), 1u);
}

TEST(InputBuffer, IgnoresDuplicatesAndOldInputs) {
  InputBuffer buffer;
  InputDropCounters drops{};
  // The redundancy: packets carrying 1..3, 2..4, 3..5.
  for (std::uint32_t first = 1; first <= 3; ++first) {
    for (std::uint32_t s = first; s < first + 3; ++s) buffer.offer(input(s), drops);
  }
  EXPECT_EQ(buffer.buffered(), 4u);  // max_depth 4: 2..5 kept, 1 skipped
  EXPECT_EQ(count(drops, InputDrop::Stale), 4u);
  EXPECT_EQ(count(drops, InputDrop::Skipped), 1u);
  bool repeated = false;
  EXPECT_EQ(buffer.next(repeated).sequence, 2u);
  buffer.offer(input(2), drops);  // already applied
  buffer.offer(input(1), drops);  // older
  EXPECT_EQ(count(drops, InputDrop::Stale), 6u);
  EXPECT_EQ(buffer.next(repeated).sequence, 3u);
}

TEST(InputBuffer, SkipsAGapForGood) {
  InputBuffer buffer;
  InputDropCounters drops{};
  bool repeated = false;
  buffer.offer(input(1), drops);
  EXPECT_EQ(buffer.next(repeated).sequence, 1u);
  buffer.offer(input(3), drops);  // 2 was lost in every packet
  EXPECT_EQ(buffer.next(repeated).sequence, 3u);
  buffer.offer(input(2), drops);  // too late now
  EXPECT_EQ(count(drops, InputDrop::Stale), 1u);
  EXPECT_EQ(buffer.next(repeated).sequence, 3u);
  EXPECT_TRUE(repeated);
}

TEST(InputBuffer, BoundsTheDelayAfterAStall) {
  InputBuffer buffer(InputBufferConfig{2});
  InputDropCounters drops{};
  for (std::uint32_t s = 1; s <= 6; ++s) buffer.offer(input(s), drops);
  EXPECT_EQ(buffer.buffered(), 2u);
  EXPECT_EQ(count(drops, InputDrop::Skipped), 4u);
  bool repeated = false;
  EXPECT_EQ(buffer.next(repeated).sequence, 5u);
  EXPECT_EQ(buffer.next(repeated).sequence, 6u);
}

TEST(InputBuffer, RefusesASequenceFarAhead) {
  InputBuffer buffer;
  InputDropCounters drops{};
  buffer.offer(input(1025), drops);
  buffer.offer(input(0xFFFFFFFFu), drops);
  EXPECT_EQ(count(drops, InputDrop::TooFarAhead), 2u);
  buffer.offer(input(1024), drops);
  EXPECT_EQ(buffer.buffered(), 1u);
}

TEST(InputBuffer, ResetForgetsTheSequence) {
  InputBuffer buffer;
  InputDropCounters drops{};
  bool repeated = false;
  buffer.offer(input(50), drops);
  buffer.offer(input(51), drops);
  EXPECT_EQ(buffer.next(repeated).sequence, 50u);
  buffer.reset();
  EXPECT_EQ(buffer.last_applied_sequence(), 0u);
  EXPECT_EQ(buffer.buffered(), 0u);
  buffer.offer(input(1), drops);  // a reconnected client starts again at 1
  EXPECT_EQ(buffer.next(repeated).sequence, 1u);
}

TEST(InputBufferConfig, ValidatesTheDepth) {
  EXPECT_EQ(InputBufferConfig{}.validate(), "");
  EXPECT_EQ(InputBufferConfig{0}.validate(), "input max_depth must be 1..32, got 0");
  EXPECT_EQ(InputBufferConfig{33}.validate(), "input max_depth must be 1..32, got 33");
}

TEST(InputDrop, EveryReasonHasAName) {
  for (std::size_t k = 0; k < kInputDropCount; ++k) {
    EXPECT_STRNE(name(static_cast<InputDrop>(k)), "unknown");
  }
}

}  // namespace
}  // namespace ricochet::server::input_buffer_test
