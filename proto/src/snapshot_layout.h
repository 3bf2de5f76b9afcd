#pragma once
/// The entity fields of the snapshot stream, shared by the encoder and the decoder so both read
/// one definition (PROTOCOL.snapshot.md §entity fields).

#include <array>
#include <cstdint>

#include "ricochet/proto/bit_stream.h"
#include "ricochet/proto/quantize.h"

namespace ricochet::proto::snapshot_layout {

/// Bits of each Exp-Golomb order written in the stream (orders 0..31).
inline constexpr int kOrderBits = 5;

/// Bit of each field in a changed entity's 4-bit mask, first written first.
enum FieldBit : std::uint8_t {
  kPositionChanged = 8,
  kVelocityChanged = 4,
  kOrientationChanged = 2,
  kFlagsChanged = 1,
};
inline constexpr int kFieldMaskBits = 4;

/// Exp-Golomb orders of the changed entities' fields in one snapshot.
struct DeltaOrders {
  int gap = 0;
  int position = 0;
  int velocity = 0;
  int orientation = 0;
};

/// Raw widths derived from the spec, computed once per encoder or decoder.
struct FieldWidths {
  std::array<int, 3> position{};  ///< bits per axis
  int velocity = 0;               ///< bits per axis of velocity + limit
  int orientation = 0;            ///< bits per component of component + limit
  std::int32_t velocity_limit = 0;
  std::int32_t orientation_limit = 0;
  std::array<std::uint32_t, 3> position_steps{};

  explicit FieldWidths(const QuantizationSpec& spec);
};

/// Which fields of `current` differ from `baseline` (a FieldBit mask; 0 when equal).
std::uint8_t changed_fields(const QuantizedEntity& baseline, const QuantizedEntity& current);

/// A new entity's state, without its id.
void write_absolute(BitWriter& out, const QuantizedEntity& entity, const FieldWidths& widths);
int absolute_bits(const QuantizedEntity& entity, const FieldWidths& widths);
/// Fills every field but the id; false on a value out of range (the reader may also fail).
bool read_absolute(BitReader& in, const FieldWidths& widths, QuantizedEntity& entity);

/// A changed entity's fields after its gap: the mask, then each changed field's delta.
void write_delta(BitWriter& out, const QuantizedEntity& baseline, const QuantizedEntity& current,
                 const DeltaOrders& orders, const FieldWidths& widths);
/// Bits write_delta takes (without the gap).
int delta_bits(const QuantizedEntity& baseline, const QuantizedEntity& current,
               const DeltaOrders& orders, const FieldWidths& widths);

enum class DeltaStatus : std::uint8_t { Ok, EmptyChange, OutOfRange };
/// Applies the delta read from `in` to `entity` (holding the baseline); the reader may fail.
DeltaStatus read_delta(BitReader& in, const DeltaOrders& orders, const FieldWidths& widths,
                       QuantizedEntity& entity);

}  // namespace ricochet::proto::snapshot_layout
