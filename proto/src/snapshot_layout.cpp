#include "snapshot_layout.h"

#include <cassert>

namespace ricochet::proto::snapshot_layout {

namespace {

bool is_identity(const QuantizedEntity& entity) {
  return entity.orientation_largest == 3 && entity.orientation == std::array<std::int32_t, 3>{};
}

bool velocity_is_zero(const QuantizedEntity& entity) {
  return entity.velocity == std::array<std::int32_t, 3>{};
}

}  // namespace

FieldWidths::FieldWidths(const QuantizationSpec& spec)
    : velocity_limit(spec.velocity_limit()), orientation_limit(spec.orientation_limit()) {
  for (int a = 0; a < 3; ++a) {
    position_steps[a] = spec.position_steps(a);
    position[a] = bits_for_count(position_steps[a]);
  }
  velocity = bits_for_count(2 * static_cast<std::uint64_t>(velocity_limit) + 1);
  orientation = bits_for_count(2 * static_cast<std::uint64_t>(orientation_limit) + 1);
}

Prediction make_prediction(std::uint32_t baseline_age, const QuantizationSpec& spec) {
  if (baseline_age == 0 || baseline_age > kMaxPredictionAge) return {};
  const std::int64_t scale = spec.prediction_scale();
  return {(baseline_age - std::int64_t{1}) * scale, (baseline_age + std::int64_t{1}) * scale};
}

std::array<std::int64_t, 3> predicted_motion(const QuantizedEntity& baseline,
                                             const std::array<std::int32_t, 3>& velocity_now,
                                             const Prediction& prediction) {
  std::array<std::int64_t, 3> motion{};
  for (int a = 0; a < 3; ++a) {
    const std::int64_t weighted = baseline.velocity[a] * prediction.baseline_weight +
                                  velocity_now[a] * prediction.current_weight;
    motion[a] = (weighted + (std::int64_t{1} << 16)) >> 17;
  }
  return motion;
}

Delta make_delta(const QuantizedEntity& baseline, const QuantizedEntity& current,
                 const FieldWidths& widths, const Prediction& prediction) {
  Delta delta;
  const std::array<std::int64_t, 3> motion =
      predicted_motion(baseline, current.velocity, prediction);
  bool velocity_changed = false, position_changed = false;
  for (int a = 0; a < 3; ++a) {
    velocity_changed = velocity_changed || baseline.velocity[a] != current.velocity[a];
    delta.velocity[a] =
        zigzag(static_cast<std::int64_t>(current.velocity[a]) - baseline.velocity[a]);
    const std::int64_t residual = static_cast<std::int64_t>(current.position[a]) -
                                  static_cast<std::int64_t>(baseline.position[a]) - motion[a];
    position_changed = position_changed || residual != 0;
    delta.position[a] = zigzag(residual);
  }
  if (velocity_changed) delta.mask |= kVelocityChanged;
  if (position_changed) delta.mask |= kPositionChanged;
  delta.same_largest = baseline.orientation_largest == current.orientation_largest;
  delta.largest = current.orientation_largest;
  bool turned = !delta.same_largest;
  for (int k = 0; k < 3; ++k) {
    turned = turned || baseline.orientation[k] != current.orientation[k];
    delta.orientation[k] =
        delta.same_largest
            ? zigzag(static_cast<std::int64_t>(current.orientation[k]) - baseline.orientation[k])
            : static_cast<std::uint64_t>(current.orientation[k] + widths.orientation_limit);
  }
  if (turned) delta.mask |= kOrientationChanged;
  if (baseline.flags != current.flags) delta.mask |= kFlagsChanged;
  delta.flags = current.flags;
  return delta;
}

/// Walks a new entity's fields once, so that writing and copying cannot disagree: `raw(value,
/// bits)` for each.
template <class Raw>
void visit_absolute(const QuantizedEntity& entity, const FieldWidths& widths, Raw&& raw) {
  for (int a = 0; a < 3; ++a) raw(entity.position[a], widths.position[a]);
  raw(velocity_is_zero(entity) ? 0 : 1, 1);
  if (!velocity_is_zero(entity)) {
    for (int a = 0; a < 3; ++a) {
      raw(static_cast<std::uint64_t>(entity.velocity[a] + widths.velocity_limit), widths.velocity);
    }
  }
  raw(is_identity(entity) ? 0 : 1, 1);
  if (!is_identity(entity)) {
    raw(entity.orientation_largest, 2);
    for (int k = 0; k < 3; ++k) {
      raw(static_cast<std::uint64_t>(entity.orientation[k] + widths.orientation_limit),
          widths.orientation);
    }
  }
  raw(entity.flags != 0 ? 1 : 0, 1);
  if (entity.flags != 0) raw(entity.flags, 8);
}

bool read_absolute(BitReader& in, const FieldWidths& widths, QuantizedEntity& entity) {
  bool in_range = true;
  for (int a = 0; a < 3; ++a) {
    entity.position[a] = static_cast<std::uint32_t>(in.read_bits(widths.position[a]));
    in_range = in_range && entity.position[a] < widths.position_steps[a];
  }
  entity.velocity = {};
  if (in.read_bool()) {
    for (int a = 0; a < 3; ++a) {
      const std::uint64_t raw = in.read_bits(widths.velocity);
      in_range = in_range && raw <= 2 * static_cast<std::uint64_t>(widths.velocity_limit);
      entity.velocity[a] =
          static_cast<std::int32_t>(static_cast<std::int64_t>(raw) - widths.velocity_limit);
    }
  }
  entity.orientation_largest = 3;
  entity.orientation = {};
  if (in.read_bool()) {
    entity.orientation_largest = static_cast<std::uint8_t>(in.read_bits(2));
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t raw = in.read_bits(widths.orientation);
      in_range = in_range && raw <= 2 * static_cast<std::uint64_t>(widths.orientation_limit);
      entity.orientation[k] =
          static_cast<std::int32_t>(static_cast<std::int64_t>(raw) - widths.orientation_limit);
    }
  }
  entity.flags = in.read_bool() ? static_cast<std::uint8_t>(in.read_bits(8)) : 0;
  return in_range;
}

namespace {

/// Walks the fields of a delta after its mask once, so that writing, counting and copying cannot
/// disagree: `code(value, order)` for each Exp-Golomb field, `raw(value, bits)` for each
/// fixed-width one.
template <class Code, class Raw>
void visit_fields(const Delta& delta, const DeltaOrders& orders, const FieldWidths& widths,
                  Code&& code, Raw&& raw) {
  const std::uint8_t mask = delta.mask;
  if (mask & kVelocityChanged) {
    for (int a = 0; a < 3; ++a) code(delta.velocity[a], orders.velocity[a]);
  }
  if (mask & kPositionChanged) {
    for (int a = 0; a < 3; ++a) code(delta.position[a], orders.position[a]);
  }
  if (mask & kOrientationChanged) {
    raw(delta.same_largest ? 1 : 0, 1);
    if (delta.same_largest) {
      for (int k = 0; k < 3; ++k) code(delta.orientation[k], orders.orientation);
    } else {
      raw(delta.largest, 2);
      for (int k = 0; k < 3; ++k) raw(delta.orientation[k], widths.orientation);
    }
  }
  if (mask & kFlagsChanged) raw(delta.flags, 8);
}

/// A DeltaBody being written: its bits, newest lowest, in one 128-bit accumulator.
class BodyWriter {
 public:
  /// Appends the low `bits` bits of value (0..64).
  void write_bits(std::uint64_t value, int bits) {
    if (bits == 0) return;
    if (bits_ + bits > DeltaBody::kMaxBits) {
      overflow_ = true;
      return;
    }
    if (bits < 64) value &= (std::uint64_t{1} << bits) - 1;
    accumulator_ = (accumulator_ << bits) | value;
    bits_ += bits;
  }
  int bits() const { return bits_; }
  DeltaBody finish() const {
    DeltaBody body;
    body.overflow = overflow_;
    if (overflow_) return body;
    body.bits = bits_;
    const Accumulator aligned = bits_ == 0 ? 0 : accumulator_ << (DeltaBody::kMaxBits - bits_);
    body.words = {static_cast<std::uint64_t>(aligned >> 64), static_cast<std::uint64_t>(aligned)};
    return body;
  }

 private:
  __extension__ typedef unsigned __int128 Accumulator;  // GCC and Clang
  static_assert(DeltaBody::kMaxBits == 128);
  Accumulator accumulator_ = 0;
  int bits_ = 0;
  bool overflow_ = false;
};

}  // namespace

void write_delta(BitWriter& out, const Delta& delta, const DeltaOrders& orders,
                 const FieldWidths& widths, std::uint8_t& previous_mask) {
  write_mask(out, delta.mask, previous_mask);
  visit_fields(
      delta, orders, widths,
      [&out](std::uint64_t value, int order) { write_code(out, value, order); },
      [&out](std::uint64_t value, int bits) { out.write_bits(value, bits); });
}

int delta_bits(const Delta& delta, const DeltaOrders& orders, const FieldWidths& widths) {
  int bits = kMaskEstimateBits;
  visit_fields(
      delta, orders, widths,
      [&bits](std::uint64_t value, int order) { bits += code_bits(value, order); },
      [&bits](std::uint64_t, int width) { bits += width; });
  return bits;
}

void write_delta_body(DeltaBody& body, const Delta& delta, const DeltaOrders& orders,
                      const FieldWidths& widths) {
  BodyWriter writer;
  visit_fields(
      delta, orders, widths,
      [&writer](std::uint64_t value, int order) {
        if (order != kAllZeroOrder) write_exp_golomb_to(writer, value, order);
      },
      [&writer](std::uint64_t value, int bits) { writer.write_bits(value, bits); });
  body = writer.finish();
}

void write_absolute_body(AbsoluteBody& body, const QuantizedEntity& entity,
                         const FieldWidths& widths) {
  // The fields fill the head until the next would not fit, then the tail (which may overflow).
  BodyWriter head, tail;
  bool in_tail = false;
  visit_absolute(entity, widths, [&](std::uint64_t value, int bits) {
    in_tail = in_tail || head.bits() + bits > DeltaBody::kMaxBits;
    (in_tail ? tail : head).write_bits(value, bits);
  });
  body.head = head.finish();
  body.tail = tail.finish();
  assert(!body.tail.overflow);  // at most 247 bits from a valid spec (snapshot_layout.h)
}

DeltaStatus read_delta(BitReader& in, const DeltaOrders& orders, const FieldWidths& widths,
                       const Prediction& prediction, std::uint8_t& previous_mask,
                       QuantizedEntity& entity) {
  const QuantizedEntity baseline = entity;
  const bool same_mask = in.read_bool();
  const auto mask =
      same_mask ? previous_mask : static_cast<std::uint8_t>(in.read_bits(kFieldMaskBits));
  previous_mask = mask;
  bool in_range = true;
  if (mask & kVelocityChanged) {
    for (int a = 0; a < 3; ++a) {
      const std::int64_t value = entity.velocity[a] + unzigzag(read_code(in, orders.velocity[a]));
      in_range = in_range && value >= -widths.velocity_limit && value <= widths.velocity_limit;
      entity.velocity[a] = in_range ? static_cast<std::int32_t>(value) : 0;
    }
  }
  if (!in_range) return DeltaStatus::OutOfRange;
  // The position follows from the velocities, then its residual if the mask says so.
  const std::array<std::int64_t, 3> motion =
      predicted_motion(baseline, entity.velocity, prediction);
  const bool has_residual = (mask & kPositionChanged) != 0;
  for (int a = 0; a < 3; ++a) {
    const std::int64_t residual = has_residual ? unzigzag(read_code(in, orders.position[a])) : 0;
    const std::int64_t value =
        static_cast<std::int64_t>(baseline.position[a]) + motion[a] + residual;
    in_range = in_range && value >= 0 && value < widths.position_steps[a];
    entity.position[a] = static_cast<std::uint32_t>(value);
  }
  if (mask & kOrientationChanged) {
    if (in.read_bool()) {
      for (int k = 0; k < 3; ++k) {
        const std::int64_t value =
            entity.orientation[k] + unzigzag(read_code(in, orders.orientation));
        in_range =
            in_range && value >= -widths.orientation_limit && value <= widths.orientation_limit;
        entity.orientation[k] = static_cast<std::int32_t>(value);
      }
    } else {
      entity.orientation_largest = static_cast<std::uint8_t>(in.read_bits(2));
      for (int k = 0; k < 3; ++k) {
        const std::uint64_t raw = in.read_bits(widths.orientation);
        in_range = in_range && raw <= 2 * static_cast<std::uint64_t>(widths.orientation_limit);
        entity.orientation[k] =
            static_cast<std::int32_t>(static_cast<std::int64_t>(raw) - widths.orientation_limit);
      }
    }
  }
  if (mask & kFlagsChanged) entity.flags = static_cast<std::uint8_t>(in.read_bits(8));
  if (!in_range) return DeltaStatus::OutOfRange;
  if (entity == baseline) return DeltaStatus::EmptyChange;
  return DeltaStatus::Ok;
}

}  // namespace ricochet::proto::snapshot_layout
