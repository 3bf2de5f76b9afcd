#pragma once
/// Quantisation of an entity's state to the integers the snapshot codec sends
/// (PROTOCOL.md Snapshots §quantisation). The server quantises its state once per tick; what a
/// client decodes equals those integers bit for bit, and dequantize() turns them back to floats.
///
/// Position: per axis, steps of position_step_m from bounds.min_m, clamped into the bounds; the
/// error inside the bounds is at most position_step_m / 2. Velocity: per axis, a signed multiple
/// of velocity_step_mps clamped to +-max_speed_mps. Orientation: smallest three, the index of the
/// largest-magnitude component (made positive, as q and -q are the same rotation) and the other
/// three as signed multiples of (1/sqrt 2) / orientation_max_step. NaN inputs quantise to the
/// bounds' minimum corner, zero velocity and the identity orientation.

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "ricochet/wire/snapshot.pb.h"

namespace ricochet::proto {

/// The map's bounds, m: every entity position the codec can send lies inside.
struct SnapshotBounds {
  std::array<float, 3> min_m{-64.0f, -16.0f, -64.0f};
  std::array<float, 3> max_m{64.0f, 48.0f, 64.0f};
};

struct QuantizationSpec {
  SnapshotBounds bounds{};
  float position_step_m = 0.001f;   ///< m, > 0 and <= 0.001 for the 1 mm guarantee
  float velocity_step_mps = 0.01f;  ///< m/s, > 0
  float max_speed_mps = 64.0f;      ///< m/s per axis, clamp of the velocity, >= velocity_step_mps
  /// Bits per smallest-three component including the sign, 4..16. 9 (Fiedler's choice) keeps
  /// the rotation within about 0.006 rad.
  int orientation_bits = 9;
  /// s per server tick (1 / tick rate), (0, 1]: the codec predicts a position from its
  /// velocities over the ticks since the baseline.
  float tick_s = 1.0f / 60;

  /// Empty when usable; otherwise names the first wrong field, its allowed range and its value.
  std::string validate() const;

  /// Number of position steps along axis a: positions quantise to [0, position_steps(a) - 1].
  std::uint32_t position_steps(int axis) const;
  /// Largest velocity magnitude in steps: velocities quantise to [-v, v].
  std::int32_t velocity_limit() const;
  /// Largest smallest-three component magnitude in steps: components lie in [-c, c].
  std::int32_t orientation_limit() const { return (1 << (orientation_bits - 1)) - 1; }
  /// Position steps one velocity step covers in one tick, in 1/65536ths:
  /// round(65536 * velocity_step_mps * tick_s / position_step_m), computed in double.
  std::int64_t prediction_scale() const;
};

/// The spec as the JoinMatchReply carries it.
void to_wire(const QuantizationSpec& spec, wire::Quantization& out);
/// Reads a spec from untrusted bytes: nullopt (with `error` set to what is wrong) when a bound is
/// missing or the spec does not validate.
std::optional<QuantizationSpec> from_wire(const wire::Quantization& in, std::string& error);

/// What the server sends of one entity, as read from its simulation.
struct EntityState {
  std::uint32_t id = 0;
  std::array<float, 3> position_m{};
  std::array<float, 3> velocity_mps{};
  std::array<float, 4> orientation_xyzw{0, 0, 0, 1};  ///< unit quaternion
  std::uint8_t flags = 0;                             ///< the game's; opaque to the codec
};

/// The integers of one entity's state in a snapshot. Equality is bit-for-bit.
struct QuantizedEntity {
  std::uint32_t id = 0;
  std::array<std::uint32_t, 3> position{};  ///< steps from bounds.min_m
  std::array<std::int32_t, 3> velocity{};   ///< steps of velocity_step_mps
  /// Index (0 x, 1 y, 2 z, 3 w) of the component left out; 3 with zero components is identity.
  std::uint8_t orientation_largest = 3;
  std::array<std::int32_t, 3> orientation{};  ///< the other three in x, y, z, w order, in steps
  std::uint8_t flags = 0;

  friend bool operator==(const QuantizedEntity&, const QuantizedEntity&) = default;
};

/// spec must be valid (spec.validate() empty). Clamps out-of-range values; NaN-safe.
QuantizedEntity quantize(const EntityState& state, const QuantizationSpec& spec);
/// The state a client shows for `entity`: bounds.min_m + steps * step (the centre of the
/// interval that rounds to it), unit orientation.
EntityState dequantize(const QuantizedEntity& entity, const QuantizationSpec& spec);
/// Only the position and velocity of dequantize() (the same floats), for a reader that has no
/// use for the orientation (a bot's view of the world), at a fraction of its cost.
void dequantize_motion(const QuantizedEntity& entity, const QuantizationSpec& spec,
                       std::array<float, 3>& position_m, std::array<float, 3>& velocity_mps);
/// True when every field of entity lies within the ranges spec allows (what the decoder checks).
bool in_range(const QuantizedEntity& entity, const QuantizationSpec& spec);

}  // namespace ricochet::proto
