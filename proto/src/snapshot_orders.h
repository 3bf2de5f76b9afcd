#pragma once
/// Picks the Exp-Golomb order that writes a set of values in the fewest bits (the encoder writes
/// it into the stream's header; PROTOCOL.md Snapshots §orders).

#include <cstdint>
#include <span>

namespace ricochet::proto::snapshot_layout {

/// Largest order the encoder tries; the stream can carry up to 31.
inline constexpr int kMaxChosenOrder = 24;

/// The order in [0, kMaxChosenOrder] minimising the total code length of `values` (0 if empty),
/// or kAllZeroOrder when every value is 0.
int best_order(std::span<const std::uint64_t> values);
/// Bits the order-k codes of `values` take together.
std::uint64_t total_bits(std::span<const std::uint64_t> values, int order);

}  // namespace ricochet::proto::snapshot_layout
