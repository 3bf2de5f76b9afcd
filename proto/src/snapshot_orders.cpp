#include "snapshot_orders.h"

#include <algorithm>

#include "ricochet/proto/bit_stream.h"
#include "snapshot_layout.h"

namespace ricochet::proto::snapshot_layout {

std::uint64_t total_bits(std::span<const std::uint64_t> values, int order) {
  std::uint64_t bits = 0;
  for (const std::uint64_t value : values) bits += exp_golomb_bits(value, order);
  return bits;
}

int best_order(std::span<const std::uint64_t> values) {
  if (!values.empty() &&
      std::all_of(values.begin(), values.end(), [](std::uint64_t v) { return v == 0; })) {
    return kAllZeroOrder;
  }
  int best = 0;
  std::uint64_t best_bits = total_bits(values, 0);
  for (int order = 1; order <= kMaxChosenOrder && !values.empty(); ++order) {
    const std::uint64_t bits = total_bits(values, order);
    if (bits < best_bits) {
      best_bits = bits;
      best = order;
    }
  }
  return best;
}

}  // namespace ricochet::proto::snapshot_layout
