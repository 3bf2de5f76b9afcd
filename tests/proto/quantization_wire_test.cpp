// The quantisation spec as the join reply carries it: a round trip gives the same spec, and a
// client refuses a spec it cannot decode with (the same checks as the server's validate()).
#include <gtest/gtest.h>

#include <limits>

#include "ricochet/proto/quantize.h"

namespace ricochet::proto::quantization_wire_test {
namespace {

QuantizationSpec arena_spec() {
  QuantizationSpec spec;
  spec.bounds.min_m = {-22, -2, -22};
  spec.bounds.max_m = {22, 12, 22};
  spec.tick_s = 1.0f / 30;
  return spec;
}

TEST(QuantizationWire, RoundTripGivesTheSameSpec) {
  wire::Quantization message;
  to_wire(arena_spec(), message);
  wire::Quantization parsed;
  ASSERT_TRUE(parsed.ParseFromString(message.SerializeAsString()));
  std::string error;
  const auto spec = from_wire(parsed, error);
  ASSERT_TRUE(spec) << error;
  EXPECT_EQ(spec->bounds.min_m, arena_spec().bounds.min_m);
  EXPECT_EQ(spec->bounds.max_m, arena_spec().bounds.max_m);
  EXPECT_EQ(spec->position_step_m, arena_spec().position_step_m);
  EXPECT_EQ(spec->velocity_step_mps, arena_spec().velocity_step_mps);
  EXPECT_EQ(spec->max_speed_mps, arena_spec().max_speed_mps);
  EXPECT_EQ(spec->orientation_bits, arena_spec().orientation_bits);
  EXPECT_EQ(spec->tick_s, arena_spec().tick_s);
  EXPECT_EQ(spec->prediction_scale(), arena_spec().prediction_scale());
}

TEST(QuantizationWire, MissingBoundsAreRefused) {
  wire::Quantization message;
  to_wire(arena_spec(), message);
  message.mutable_bounds_max_m()->RemoveLast();
  std::string error;
  EXPECT_FALSE(from_wire(message, error));
  EXPECT_NE(error.find("3 values"), std::string::npos) << error;
}

TEST(QuantizationWire, OutOfRangeFieldsAreRefusedNamingTheField) {
  const auto refused = [](auto spoil, const char* field) {
    wire::Quantization message;
    to_wire(arena_spec(), message);
    spoil(message);
    std::string error;
    EXPECT_FALSE(from_wire(message, error)) << field;
    EXPECT_NE(error.find(field), std::string::npos) << error;
  };
  refused([](wire::Quantization& m) { m.set_position_step_m(0.01f); }, "position_step_m");
  refused([](wire::Quantization& m) { m.set_velocity_step_mps(-1); }, "velocity_step_mps");
  refused([](wire::Quantization& m) { m.set_orientation_bits(40); }, "orientation_bits");
  refused([](wire::Quantization& m) { m.set_orientation_bits(2); }, "orientation_bits");
  refused([](wire::Quantization& m) { m.set_tick_s(std::numeric_limits<float>::quiet_NaN()); },
          "tick_s");
  refused([](wire::Quantization& m) { m.set_bounds_max_m(1, -5); }, "bounds");
}

}  // namespace
}  // namespace ricochet::proto::quantization_wire_test
