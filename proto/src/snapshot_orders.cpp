#include "snapshot_orders.h"

#include "ricochet/proto/bit_stream.h"
#include "snapshot_layout.h"

namespace ricochet::proto::snapshot_layout {

std::uint64_t total_bits(std::span<const std::uint64_t> values, int order) {
  std::uint64_t bits = 0;
  for (const std::uint64_t value : values) bits += exp_golomb_bits(value, order);
  return bits;
}

namespace {

/// best_order by trying every order in turn: for values of 2^63 and more, where v + 2^k may
/// wrap (never from the codec's fields, which are below 2^34).
int best_order_by_trial(std::span<const std::uint64_t> values) {
  int best = 0;
  std::uint64_t best_bits = total_bits(values, 0);
  for (int order = 1; order <= kMaxChosenOrder; ++order) {
    const std::uint64_t bits = total_bits(values, order);
    if (bits < best_bits) {
      best_bits = bits;
      best = order;
    }
  }
  return best;
}

}  // namespace

int OrderTally::best() const {
  if (count_ == 0) return 0;
  if (nonzero_ == 0) return kAllZeroOrder;
  int best = 0;
  std::int64_t best_bits = 0;
  std::int64_t wide = 0;    // sum of bit_width(v + 2^order) over values wider than order
  std::int64_t narrow = 0;  // values no wider than order
  for (int order = 0; order < kOrders; ++order) {
    wide += wide_step_[order];
    narrow += width_count_[order];
    const std::int64_t k1 = order + 1;
    const std::int64_t bits = 2 * (wide + narrow * k1) - count_ * k1;
    if (order == 0 || bits < best_bits) {
      best_bits = bits;
      best = order;
    }
  }
  return best;
}

int best_order(std::span<const std::uint64_t> values) {
  OrderTally tally;
  for (const std::uint64_t value : values) {
    if (value >> 63) return best_order_by_trial(values);
    tally.add(value);
  }
  return tally.best();
}

}  // namespace ricochet::proto::snapshot_layout
