#include "ricochet/proto/quantize.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace ricochet::proto::quantize_test {
namespace {

QuantizationSpec arena_spec() {
  QuantizationSpec spec;
  spec.bounds = {{-50.0f, -5.0f, -50.0f}, {50.0f, 25.0f, 50.0f}};
  return spec;
}

std::array<float, 4> random_unit_quaternion(std::mt19937& random) {
  std::normal_distribution<float> normal;
  std::array<float, 4> q{};
  float norm = 0;
  for (float& c : q) {
    c = normal(random);
    norm += c * c;
  }
  norm = std::sqrt(norm);
  for (float& c : q) c /= norm;
  return q;
}

TEST(Quantize, DefaultSpecIsValidAndBadFieldsAreNamed) {
  EXPECT_EQ(QuantizationSpec{}.validate(), "");
  QuantizationSpec spec;
  spec.position_step_m = 0.002f;
  EXPECT_NE(spec.validate().find("position_step_m"), std::string::npos);
  spec = {};
  spec.bounds.max_m[1] = spec.bounds.min_m[1];
  EXPECT_NE(spec.validate().find("bounds.y"), std::string::npos);
  spec = {};
  spec.orientation_bits = 3;
  EXPECT_NE(spec.validate().find("orientation_bits must be 4..16, got 3"), std::string::npos);
  spec = {};
  spec.max_speed_mps = std::numeric_limits<float>::infinity();
  EXPECT_NE(spec.validate().find("max_speed_mps"), std::string::npos);
}

TEST(Quantize, PositionsWithinBoundsAreWithinHalfAMillimetre) {
  const QuantizationSpec spec = arena_spec();
  std::mt19937 random(1);
  double worst_m = 0;
  for (int i = 0; i < 20000; ++i) {
    EntityState state;
    for (int a = 0; a < 3; ++a) {
      std::uniform_real_distribution<float> axis(spec.bounds.min_m[a], spec.bounds.max_m[a]);
      state.position_m[a] = axis(random);
    }
    const EntityState back = dequantize(quantize(state, spec), spec);
    for (int a = 0; a < 3; ++a) {
      worst_m = std::max(worst_m,
                         std::fabs(static_cast<double>(back.position_m[a]) - state.position_m[a]));
    }
  }
  // Half a step plus float rounding of coordinates up to 50 m (ulp 3.8e-6 m).
  EXPECT_LE(worst_m, 0.0005 + 1e-5);
}

TEST(Quantize, VelocityErrorIsHalfAStepAndClampsAtMaxSpeed) {
  const QuantizationSpec spec = arena_spec();
  std::mt19937 random(2);
  std::uniform_real_distribution<float> speed(-spec.max_speed_mps, spec.max_speed_mps);
  for (int i = 0; i < 10000; ++i) {
    EntityState state;
    for (float& v : state.velocity_mps) v = speed(random);
    const EntityState back = dequantize(quantize(state, spec), spec);
    for (int a = 0; a < 3; ++a) {
      ASSERT_LE(std::fabs(back.velocity_mps[a] - state.velocity_mps[a]),
                spec.velocity_step_mps / 2 + 1e-5f);
    }
  }
  EntityState fast;
  fast.velocity_mps = {1e9f, -1e9f, 3.0f};
  const QuantizedEntity q = quantize(fast, spec);
  EXPECT_EQ(q.velocity[0], spec.velocity_limit());
  EXPECT_EQ(q.velocity[1], -spec.velocity_limit());
  EXPECT_EQ(q.velocity[2], 300);
}

TEST(Quantize, OrientationSmallestThreeIsWithinAFewMilliradians) {
  const QuantizationSpec spec = arena_spec();
  std::mt19937 random(3);
  double worst_rad = 0;
  for (int i = 0; i < 20000; ++i) {
    EntityState state;
    state.orientation_xyzw = random_unit_quaternion(random);
    const QuantizedEntity q = quantize(state, spec);
    ASSERT_TRUE(in_range(q, spec));
    const EntityState back = dequantize(q, spec);
    double dot = 0;
    for (int k = 0; k < 4; ++k)
      dot += static_cast<double>(back.orientation_xyzw[k]) * state.orientation_xyzw[k];
    worst_rad = std::max(worst_rad, 2 * std::acos(std::min(1.0, std::fabs(dot))));
  }
  // 9 bits: a component step of 0.0028; the rotation angle error stays under 0.008 rad.
  EXPECT_LT(worst_rad, 0.008);
}

TEST(Quantize, IdentityIsLargestWWithZeroComponentsAndSignDoesNotMatter) {
  const QuantizationSpec spec = arena_spec();
  EntityState state;
  EXPECT_EQ(quantize(state, spec).orientation_largest, 3);
  EXPECT_EQ(quantize(state, spec).orientation, (std::array<std::int32_t, 3>{}));
  EntityState turned;
  turned.orientation_xyzw = {0.6f, 0.0f, 0.0f, 0.8f};
  EntityState negated;
  negated.orientation_xyzw = {-0.6f, -0.0f, -0.0f, -0.8f};
  EXPECT_EQ(quantize(turned, spec), quantize(negated, spec));
}

TEST(Quantize, NanAndOutOfBoundsAreClampedNotPropagated) {
  const QuantizationSpec spec = arena_spec();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  EntityState state;
  state.id = 9;
  state.position_m = {nan, inf, -inf};
  state.velocity_mps = {nan, inf, -inf};
  state.orientation_xyzw = {nan, 0, 0, 1};
  state.flags = 0xA5;
  const QuantizedEntity q = quantize(state, spec);
  EXPECT_TRUE(in_range(q, spec));
  EXPECT_EQ(q.id, 9u);
  EXPECT_EQ(q.flags, 0xA5);
  EXPECT_EQ(q.position[0], 0u);
  EXPECT_EQ(q.position[1], spec.position_steps(1) - 1);
  EXPECT_EQ(q.position[2], 0u);
  EXPECT_EQ(q.velocity[0], 0);
  EXPECT_EQ(q.velocity[1], spec.velocity_limit());
  EXPECT_EQ(q.velocity[2], -spec.velocity_limit());
  EXPECT_EQ(q.orientation_largest, 3);
  const EntityState back = dequantize(q, spec);
  for (const float c : back.orientation_xyzw) EXPECT_TRUE(std::isfinite(c));
  EXPECT_FLOAT_EQ(back.position_m[1], spec.bounds.max_m[1]);
}

TEST(Quantize, QuantizingADequantizedPositionAndVelocityGivesTheSameIntegers) {
  const QuantizationSpec spec = arena_spec();
  std::mt19937 random(4);
  for (int i = 0; i < 5000; ++i) {
    EntityState state;
    for (int a = 0; a < 3; ++a) {
      std::uniform_real_distribution<float> axis(spec.bounds.min_m[a], spec.bounds.max_m[a]);
      state.position_m[a] = axis(random);
      state.velocity_mps[a] = axis(random);
    }
    const QuantizedEntity q = quantize(state, spec);
    const QuantizedEntity again = quantize(dequantize(q, spec), spec);
    ASSERT_EQ(again.position, q.position) << "entity " << i;
    ASSERT_EQ(again.velocity, q.velocity) << "entity " << i;
  }
}

}  // namespace
}  // namespace ricochet::proto::quantize_test
