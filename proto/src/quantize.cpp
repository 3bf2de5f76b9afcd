#include "ricochet/proto/quantize.h"

#include <algorithm>
#include <cmath>

namespace ricochet::proto {

namespace {

/// Larger spans would let a position delta exceed what the codec's variable-length codes carry.
constexpr double kMaxPositionSteps = 2147483647.0;
constexpr double kMaxVelocitySteps = 1073741823.0;
constexpr double kSqrt2 = 1.4142135623730951;
/// Keeps the codec's prediction products within 64 bits (PROTOCOL.md Snapshots §prediction).
constexpr std::int64_t kMaxPredictionScale = std::int64_t{1} << 23;

/// NaN gives `if_nan`.
std::int64_t round_clamped(double value, double low, double high, std::int64_t if_nan) {
  if (!(value == value)) return if_nan;
  return static_cast<std::int64_t>(std::llround(std::clamp(value, low, high)));
}

double axis_span_steps(const QuantizationSpec& spec, int axis) {
  const double span = static_cast<double>(spec.bounds.max_m[axis]) - spec.bounds.min_m[axis];
  return std::floor(span / spec.position_step_m + 0.5);
}

}  // namespace

std::string QuantizationSpec::validate() const {
  static constexpr const char* kAxis[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(bounds.min_m[a]) || !std::isfinite(bounds.max_m[a]) ||
        !(bounds.min_m[a] < bounds.max_m[a])) {
      return std::string("bounds.") + kAxis[a] + " must be finite with min_m < max_m, got " +
             std::to_string(bounds.min_m[a]) + " .. " + std::to_string(bounds.max_m[a]);
    }
  }
  if (!(position_step_m > 0 && position_step_m <= 0.001f)) {
    return "position_step_m must be in (0, 0.001] m, got " + std::to_string(position_step_m);
  }
  for (int a = 0; a < 3; ++a) {
    if (axis_span_steps(*this, a) + 1 > kMaxPositionSteps) {
      return std::string("bounds.") + kAxis[a] +
             " span / position_step_m must be < 2^31 steps, got " +
             std::to_string(axis_span_steps(*this, a) + 1);
    }
  }
  if (!(velocity_step_mps > 0) || !std::isfinite(velocity_step_mps)) {
    return "velocity_step_mps must be finite and > 0, got " + std::to_string(velocity_step_mps);
  }
  if (!(max_speed_mps >= velocity_step_mps) || !std::isfinite(max_speed_mps) ||
      static_cast<double>(max_speed_mps) / velocity_step_mps > kMaxVelocitySteps) {
    return "max_speed_mps must be finite, >= velocity_step_mps and < 2^30 steps, got " +
           std::to_string(max_speed_mps);
  }
  if (orientation_bits < 4 || orientation_bits > 16) {
    return "orientation_bits must be 4..16, got " + std::to_string(orientation_bits);
  }
  if (!(tick_s > 0 && tick_s <= 1)) {
    return "tick_s must be in (0, 1] s, got " + std::to_string(tick_s);
  }
  if (prediction_scale() > kMaxPredictionScale) {
    return "velocity_step_mps * tick_s / position_step_m must be <= 128, got " +
           std::to_string(static_cast<double>(prediction_scale()) / 65536);
  }
  return {};
}

std::uint32_t QuantizationSpec::position_steps(int axis) const {
  return static_cast<std::uint32_t>(axis_span_steps(*this, axis)) + 1;
}

std::int32_t QuantizationSpec::velocity_limit() const {
  return static_cast<std::int32_t>(
      std::floor(static_cast<double>(max_speed_mps) / velocity_step_mps + 0.5));
}

std::int64_t QuantizationSpec::prediction_scale() const {
  return std::llround(65536.0 * static_cast<double>(velocity_step_mps) *
                      static_cast<double>(tick_s) / static_cast<double>(position_step_m));
}

QuantizedEntity quantize(const EntityState& state, const QuantizationSpec& spec) {
  QuantizedEntity out;
  out.id = state.id;
  out.flags = state.flags;
  const double velocity_limit = spec.velocity_limit();
  for (int a = 0; a < 3; ++a) {
    const double steps =
        (static_cast<double>(state.position_m[a]) - spec.bounds.min_m[a]) / spec.position_step_m;
    out.position[a] = static_cast<std::uint32_t>(
        round_clamped(steps, 0, static_cast<double>(spec.position_steps(a) - 1), 0));
    out.velocity[a] = static_cast<std::int32_t>(
        round_clamped(static_cast<double>(state.velocity_mps[a]) / spec.velocity_step_mps,
                      -velocity_limit, velocity_limit, 0));
  }

  std::array<double, 4> q{};
  double norm_squared = 0;
  for (int i = 0; i < 4; ++i) {
    q[i] = state.orientation_xyzw[i];
    norm_squared += q[i] * q[i];
  }
  if (!std::isfinite(norm_squared) || norm_squared < 1e-12) return out;  // identity
  const double inverse_norm = 1.0 / std::sqrt(norm_squared);
  int largest = 0;
  for (int i = 1; i < 4; ++i) {
    if (std::fabs(q[i]) > std::fabs(q[largest])) largest = i;
  }
  const double sign = q[largest] < 0 ? -inverse_norm : inverse_norm;
  const double limit = spec.orientation_limit();
  out.orientation_largest = static_cast<std::uint8_t>(largest);
  for (int i = 0, k = 0; i < 4; ++i) {
    if (i == largest) continue;
    out.orientation[k++] =
        static_cast<std::int32_t>(round_clamped(q[i] * sign * kSqrt2 * limit, -limit, limit, 0));
  }
  return out;
}

EntityState dequantize(const QuantizedEntity& entity, const QuantizationSpec& spec) {
  EntityState out;
  out.id = entity.id;
  out.flags = entity.flags;
  dequantize_motion(entity, spec, out.position_m, out.velocity_mps);
  const double scale = 1.0 / (kSqrt2 * spec.orientation_limit());
  std::array<double, 4> q{};
  double sum_squared = 0;
  const int largest = entity.orientation_largest & 3;
  for (int i = 0, k = 0; i < 4; ++i) {
    if (i == largest) continue;
    q[i] = entity.orientation[k++] * scale;
    sum_squared += q[i] * q[i];
  }
  q[largest] = std::sqrt(std::max(0.0, 1.0 - sum_squared));
  double norm = 0;
  for (const double c : q) norm += c * c;
  norm = std::sqrt(norm);
  for (int i = 0; i < 4; ++i) out.orientation_xyzw[i] = static_cast<float>(q[i] / norm);
  return out;
}

void dequantize_motion(const QuantizedEntity& entity, const QuantizationSpec& spec,
                       std::array<float, 3>& position_m, std::array<float, 3>& velocity_mps) {
  for (int a = 0; a < 3; ++a) {
    position_m[a] = static_cast<float>(
        spec.bounds.min_m[a] + static_cast<double>(entity.position[a]) * spec.position_step_m);
    velocity_mps[a] =
        static_cast<float>(static_cast<double>(entity.velocity[a]) * spec.velocity_step_mps);
  }
}

bool in_range(const QuantizedEntity& entity, const QuantizationSpec& spec) {
  const std::int32_t velocity_limit = spec.velocity_limit();
  const std::int32_t orientation_limit = spec.orientation_limit();
  for (int a = 0; a < 3; ++a) {
    if (entity.position[a] >= spec.position_steps(a)) return false;
    if (entity.velocity[a] < -velocity_limit || entity.velocity[a] > velocity_limit) return false;
    if (entity.orientation[a] < -orientation_limit || entity.orientation[a] > orientation_limit) {
      return false;
    }
  }
  return entity.orientation_largest <= 3;
}

void to_wire(const QuantizationSpec& spec, wire::Quantization& out) {
  out.Clear();
  for (int axis = 0; axis < 3; ++axis) {
    out.add_bounds_min_m(spec.bounds.min_m[static_cast<std::size_t>(axis)]);
    out.add_bounds_max_m(spec.bounds.max_m[static_cast<std::size_t>(axis)]);
  }
  out.set_position_step_m(spec.position_step_m);
  out.set_velocity_step_mps(spec.velocity_step_mps);
  out.set_max_speed_mps(spec.max_speed_mps);
  out.set_orientation_bits(static_cast<std::uint32_t>(spec.orientation_bits));
  out.set_tick_s(spec.tick_s);
}

std::optional<QuantizationSpec> from_wire(const wire::Quantization& in, std::string& error) {
  if (in.bounds_min_m_size() != 3 || in.bounds_max_m_size() != 3) {
    error = "quantization bounds must have 3 values each, got " +
            std::to_string(in.bounds_min_m_size()) + " and " +
            std::to_string(in.bounds_max_m_size());
    return std::nullopt;
  }
  if (in.orientation_bits() > 16) {
    error =
        "quantization orientation_bits must be 4..16, got " + std::to_string(in.orientation_bits());
    return std::nullopt;
  }
  QuantizationSpec spec;
  for (int axis = 0; axis < 3; ++axis) {
    spec.bounds.min_m[static_cast<std::size_t>(axis)] = in.bounds_min_m(axis);
    spec.bounds.max_m[static_cast<std::size_t>(axis)] = in.bounds_max_m(axis);
  }
  spec.position_step_m = in.position_step_m();
  spec.velocity_step_mps = in.velocity_step_mps();
  spec.max_speed_mps = in.max_speed_mps();
  spec.orientation_bits = static_cast<int>(in.orientation_bits());
  spec.tick_s = in.tick_s();
  error = spec.validate();
  if (!error.empty()) return std::nullopt;
  return spec;
}

}  // namespace ricochet::proto
