#pragma once
/// The entity fields of the snapshot stream, shared by the encoder and the decoder so both read
/// one definition (PROTOCOL.md Snapshots §entity fields).

#include <array>
#include <cstdint>

#include "ricochet/proto/bit_stream.h"
#include "ricochet/proto/quantize.h"

namespace ricochet::proto::snapshot_layout {

/// Bits of each Exp-Golomb order written in the stream (orders 0..31).
inline constexpr int kOrderBits = 5;
/// The order that says every value coded with it is 0 and takes no bits.
inline constexpr int kAllZeroOrder = 31;

/// An Exp-Golomb code of `order`, or nothing for kAllZeroOrder (value must then be 0).
inline void write_code(BitWriter& out, std::uint64_t value, int order) {
  if (order != kAllZeroOrder) out.write_exp_golomb(value, order);
}
inline int code_bits(std::uint64_t value, int order) {
  return order == kAllZeroOrder ? 0 : exp_golomb_bits(value, order);
}
inline std::uint64_t read_code(BitReader& in, int order) {
  return order == kAllZeroOrder ? 0 : in.read_exp_golomb(order);
}

/// Bit of each field in a changed entity's 4-bit mask, in the order the fields follow it.
enum FieldBit : std::uint8_t {
  kVelocityChanged = 8,
  kPositionChanged = 4,
  kOrientationChanged = 2,
  kFlagsChanged = 1,
};
inline constexpr int kFieldMaskBits = 4;
/// The mask a stream's first changed entity is compared with (velocity and position).
inline constexpr std::uint8_t kInitialFieldMask = kVelocityChanged | kPositionChanged;

/// Exp-Golomb orders of the changed entities' fields in one snapshot, in stream order.
struct DeltaOrders {
  int gap = 0;
  std::array<int, 3> velocity{};  ///< per axis
  std::array<int, 3> position{};  ///< per axis, of the residual after prediction
  int orientation = 0;            ///< the three components
};
inline constexpr int kDeltaOrderCount = 8;
static_assert(sizeof(DeltaOrders) == kDeltaOrderCount * sizeof(int), "one order per field");

/// Baselines older than this many ticks get no position prediction.
inline constexpr std::uint32_t kMaxPredictionAge = 255;

/// The weights of the baseline's and the current velocity in a changed entity's predicted
/// motion: (age - 1) * scale and (age + 1) * scale, or both 0 past kMaxPredictionAge
/// (PROTOCOL.md Snapshots §6). With velocity integrated before position (semi-implicit Euler),
/// a velocity changing linearly over the age is predicted exactly.
struct Prediction {
  std::int64_t baseline_weight = 0;
  std::int64_t current_weight = 0;

  friend bool operator==(const Prediction&, const Prediction&) = default;
};
Prediction make_prediction(std::uint32_t baseline_age, const QuantizationSpec& spec);

/// Position steps an entity is predicted to have moved along each axis since its baseline:
/// floor((v_baseline * baseline_weight + v_now * current_weight + 2^16) / 2^17).
std::array<std::int64_t, 3> predicted_motion(const QuantizedEntity& baseline,
                                             const std::array<std::int32_t, 3>& velocity_now,
                                             const Prediction& prediction);

/// Raw widths derived from the spec, computed once per encoder or decoder.
struct FieldWidths {
  std::array<int, 3> position{};  ///< bits per axis
  int velocity = 0;               ///< bits per axis of velocity + limit
  int orientation = 0;            ///< bits per component of component + limit
  std::int32_t velocity_limit = 0;
  std::int32_t orientation_limit = 0;
  std::array<std::uint32_t, 3> position_steps{};

  explicit FieldWidths(const QuantizationSpec& spec);
  friend bool operator==(const FieldWidths&, const FieldWidths&) = default;
};

/// A changed entity's delta, worked out once so that the encoder counts and writes the same
/// values. `mask` marks (FieldBit) velocity, orientation and flags when they differ from the
/// baseline, position when it differs from the prediction; it may be 0 for an entity that
/// moved exactly as predicted. The arrays hold what write_delta writes for each marked field.
struct Delta {
  std::uint8_t mask = 0;
  std::array<std::uint64_t, 3> velocity{};  ///< zig-zag velocity deltas, per axis
  std::array<std::uint64_t, 3> position{};  ///< zig-zag position residuals after prediction
  bool same_largest = false;                ///< orientation: the same largest component
  std::uint8_t largest = 0;                 ///< orientation: the current largest component
  /// Orientation: zig-zag component deltas when same_largest, else component + limit.
  std::array<std::uint64_t, 3> orientation{};
  std::uint8_t flags = 0;  ///< the current flags
};
Delta make_delta(const QuantizedEntity& baseline, const QuantizedEntity& current,
                 const FieldWidths& widths, const Prediction& prediction);

/// Fills every field but the id; false on a value out of range (the reader may also fail).
bool read_absolute(BitReader& in, const FieldWidths& widths, QuantizedEntity& entity);

/// A changed entity's fields after its gap: the mask (1 bit when it equals `previous_mask`, else
/// 0 and 4 bits; updated), then each marked field's delta.
void write_delta(BitWriter& out, const Delta& delta, const DeltaOrders& orders,
                 const FieldWidths& widths, std::uint8_t& previous_mask);
/// Bits write_delta takes (without the gap), its mask counted as kMaskEstimateBits.
int delta_bits(const Delta& delta, const DeltaOrders& orders, const FieldWidths& widths);
/// What an estimate counts for a mask, not knowing whether it repeats the previous one.
inline constexpr int kMaskEstimateBits = 1 + kFieldMaskBits;

/// The fields write_delta writes after the mask, written once for one set of orders (the gap
/// order aside), so that an encoder counts a delta and then copies its bits into the stream,
/// and the encoders of other clients holding the same baseline copy them too. A delta longer
/// than kMaxBits (a teleport among small changes) overflows and is written field by field.
struct DeltaBody {
  static constexpr int kMaxBits = 128;
  std::array<std::uint64_t, 2> words{};  ///< the bits from bit 63 of words[0] on
  int bits = 0;
  bool overflow = false;
};
/// Writes `delta`'s fields with the velocity, position and orientation orders of `orders`.
void write_delta_body(DeltaBody& body, const Delta& delta, const DeltaOrders& orders,
                      const FieldWidths& widths);
/// The mask: 1 when it equals previous_mask, else 0 and its 4 bits; previous_mask updated.
inline void write_mask(BitWriter& out, std::uint8_t mask, std::uint8_t& previous_mask) {
  if (mask == previous_mask) {
    out.write_bits(1, 1);
  } else {
    out.write_bits(mask, 1 + kFieldMaskBits);  // a 0, then the mask
    previous_mask = mask;
  }
}
/// Copies a body that did not overflow.
inline void write_body(BitWriter& out, const DeltaBody& body) {
  if (body.bits > 64) {
    out.write_bits(body.words[0], 64);
    out.write_bits(body.words[1] >> (128 - body.bits), body.bits - 64);
  } else if (body.bits > 0) {
    out.write_bits(body.words[0] >> (64 - body.bits), body.bits);
  }
}
/// write_delta from a body that did not overflow: the mask, then the body's bits.
inline void write_delta(BitWriter& out, std::uint8_t mask, const DeltaBody& body,
                        std::uint8_t& previous_mask) {
  write_mask(out, mask, previous_mask);
  write_body(out, body);
}

/// A new entity's state without its id, written once so that every client it is new to gets a
/// copy: the fields that fit DeltaBody::kMaxBits in `head`, the rest in `tail`. The state of a
/// valid spec takes at most 247 bits (31 per position and velocity axis, 16 per orientation
/// component, 13 of flags, booleans and the largest component: quantize.h's limits), so it
/// always fits.
struct AbsoluteBody {
  DeltaBody head, tail;
};
void write_absolute_body(AbsoluteBody& body, const QuantizedEntity& entity,
                         const FieldWidths& widths);
inline void write_absolute(BitWriter& out, const AbsoluteBody& body) {
  write_body(out, body.head);
  write_body(out, body.tail);
}
/// The orders that write a delta's fields (all but the gap order) packed in one integer: two
/// sets of orders with the same key write every delta's fields alike.
inline std::uint64_t field_orders_key(const DeltaOrders& orders) {
  std::uint64_t key = static_cast<std::uint64_t>(orders.orientation);
  for (int a = 0; a < 3; ++a) {
    key = (key << 6) | static_cast<std::uint64_t>(orders.velocity[a]);
    key = (key << 6) | static_cast<std::uint64_t>(orders.position[a]);
  }
  return key;
}

enum class DeltaStatus : std::uint8_t { Ok, EmptyChange, OutOfRange };
/// Applies the delta read from `in` to `entity` (holding the baseline); the reader may fail.
/// EmptyChange: the result equals the baseline.
DeltaStatus read_delta(BitReader& in, const DeltaOrders& orders, const FieldWidths& widths,
                       const Prediction& prediction, std::uint8_t& previous_mask,
                       QuantizedEntity& entity);

}  // namespace ricochet::proto::snapshot_layout
