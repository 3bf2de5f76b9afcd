#include "snapshot_layout.h"

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

std::uint8_t changed_fields(const QuantizedEntity& baseline, const QuantizedEntity& current) {
  std::uint8_t mask = 0;
  if (baseline.position != current.position) mask |= kPositionChanged;
  if (baseline.velocity != current.velocity) mask |= kVelocityChanged;
  if (baseline.orientation_largest != current.orientation_largest ||
      baseline.orientation != current.orientation) {
    mask |= kOrientationChanged;
  }
  if (baseline.flags != current.flags) mask |= kFlagsChanged;
  return mask;
}

void write_absolute(BitWriter& out, const QuantizedEntity& entity, const FieldWidths& widths) {
  for (int a = 0; a < 3; ++a) out.write_bits(entity.position[a], widths.position[a]);
  out.write_bool(!velocity_is_zero(entity));
  if (!velocity_is_zero(entity)) {
    for (int a = 0; a < 3; ++a) {
      out.write_bits(static_cast<std::uint64_t>(entity.velocity[a] + widths.velocity_limit),
                     widths.velocity);
    }
  }
  out.write_bool(!is_identity(entity));
  if (!is_identity(entity)) {
    out.write_bits(entity.orientation_largest, 2);
    for (int k = 0; k < 3; ++k) {
      out.write_bits(static_cast<std::uint64_t>(entity.orientation[k] + widths.orientation_limit),
                     widths.orientation);
    }
  }
  out.write_bool(entity.flags != 0);
  if (entity.flags != 0) out.write_bits(entity.flags, 8);
}

int absolute_bits(const QuantizedEntity& entity, const FieldWidths& widths) {
  int bits = widths.position[0] + widths.position[1] + widths.position[2] + 3;
  if (!velocity_is_zero(entity)) bits += 3 * widths.velocity;
  if (!is_identity(entity)) bits += 2 + 3 * widths.orientation;
  if (entity.flags != 0) bits += 8;
  return bits;
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

void write_delta(BitWriter& out, const QuantizedEntity& baseline, const QuantizedEntity& current,
                 const DeltaOrders& orders, const FieldWidths& widths) {
  const std::uint8_t mask = changed_fields(baseline, current);
  out.write_bits(mask, kFieldMaskBits);
  if (mask & kPositionChanged) {
    for (int a = 0; a < 3; ++a) {
      out.write_signed_exp_golomb(static_cast<std::int64_t>(current.position[a]) -
                                      static_cast<std::int64_t>(baseline.position[a]),
                                  orders.position);
    }
  }
  if (mask & kVelocityChanged) {
    for (int a = 0; a < 3; ++a) {
      out.write_signed_exp_golomb(
          static_cast<std::int64_t>(current.velocity[a]) - baseline.velocity[a], orders.velocity);
    }
  }
  if (mask & kOrientationChanged) {
    const bool same_largest = current.orientation_largest == baseline.orientation_largest;
    out.write_bool(same_largest);
    if (same_largest) {
      for (int k = 0; k < 3; ++k) {
        out.write_signed_exp_golomb(
            static_cast<std::int64_t>(current.orientation[k]) - baseline.orientation[k],
            orders.orientation);
      }
    } else {
      out.write_bits(current.orientation_largest, 2);
      for (int k = 0; k < 3; ++k) {
        out.write_bits(
            static_cast<std::uint64_t>(current.orientation[k] + widths.orientation_limit),
            widths.orientation);
      }
    }
  }
  if (mask & kFlagsChanged) out.write_bits(current.flags, 8);
}

int delta_bits(const QuantizedEntity& baseline, const QuantizedEntity& current,
               const DeltaOrders& orders, const FieldWidths& widths) {
  const std::uint8_t mask = changed_fields(baseline, current);
  int bits = kFieldMaskBits;
  if (mask & kPositionChanged) {
    for (int a = 0; a < 3; ++a) {
      bits += exp_golomb_bits(zigzag(static_cast<std::int64_t>(current.position[a]) -
                                     static_cast<std::int64_t>(baseline.position[a])),
                              orders.position);
    }
  }
  if (mask & kVelocityChanged) {
    for (int a = 0; a < 3; ++a) {
      bits += exp_golomb_bits(
          zigzag(static_cast<std::int64_t>(current.velocity[a]) - baseline.velocity[a]),
          orders.velocity);
    }
  }
  if (mask & kOrientationChanged) {
    bits += 1;
    if (current.orientation_largest == baseline.orientation_largest) {
      for (int k = 0; k < 3; ++k) {
        bits += exp_golomb_bits(
            zigzag(static_cast<std::int64_t>(current.orientation[k]) - baseline.orientation[k]),
            orders.orientation);
      }
    } else {
      bits += 2 + 3 * widths.orientation;
    }
  }
  if (mask & kFlagsChanged) bits += 8;
  return bits;
}

DeltaStatus read_delta(BitReader& in, const DeltaOrders& orders, const FieldWidths& widths,
                       QuantizedEntity& entity) {
  const auto mask = static_cast<std::uint8_t>(in.read_bits(kFieldMaskBits));
  if (in.failed()) return DeltaStatus::Ok;  // the caller reports the truncation
  if (mask == 0) return DeltaStatus::EmptyChange;
  bool in_range = true;
  if (mask & kPositionChanged) {
    for (int a = 0; a < 3; ++a) {
      const std::int64_t value = static_cast<std::int64_t>(entity.position[a]) +
                                 in.read_signed_exp_golomb(orders.position);
      in_range = in_range && value >= 0 && value < widths.position_steps[a];
      entity.position[a] = static_cast<std::uint32_t>(value);
    }
  }
  if (mask & kVelocityChanged) {
    for (int a = 0; a < 3; ++a) {
      const std::int64_t value = entity.velocity[a] + in.read_signed_exp_golomb(orders.velocity);
      in_range = in_range && value >= -widths.velocity_limit && value <= widths.velocity_limit;
      entity.velocity[a] = static_cast<std::int32_t>(value);
    }
  }
  if (mask & kOrientationChanged) {
    if (in.read_bool()) {
      for (int k = 0; k < 3; ++k) {
        const std::int64_t value =
            entity.orientation[k] + in.read_signed_exp_golomb(orders.orientation);
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
  return in_range ? DeltaStatus::Ok : DeltaStatus::OutOfRange;
}

}  // namespace ricochet::proto::snapshot_layout
