#include "snapshot_orders.h"

#include <array>
#include <bit>

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

int best_order(std::span<const std::uint64_t> values) {
  if (values.empty()) return 0;
  // The order-k code of v takes 2 * bit_width(v + 2^k) - k - 1 bits. With w = bit_width(v):
  // for k >= w, v < 2^k and bit_width(v + 2^k) = k + 1; for k < w it is w, or w + 1 when bits
  // w-1..k of v are all ones (v + 2^k carries into bit w), that is when k >= w - (v's leading
  // ones). So each value adds w to the orders [0, w) and 1 more to [w - ones, w), written as
  // differences; one pass over the values gives every order's total exactly, as total_bits
  // would, instead of one pass per order.
  constexpr int kOrders = kMaxChosenOrder + 1;
  std::array<std::int64_t, kOrders + 1> wide_step{};     // differences of sum over wider values
  std::array<std::uint64_t, kOrders + 1> width_count{};  // values of bit_width w, w < kOrders
  bool all_zero = true;
  for (const std::uint64_t value : values) {
    all_zero = all_zero && value == 0;
    const int width = std::bit_width(value);
    if (width == 64) return best_order_by_trial(values);
    if (width < kOrders) ++width_count[width];
    if (width == 0) continue;
    const int end = width < kOrders ? width : kOrders;
    wide_step[0] += width;
    wide_step[end] -= width;
    const int carry_from = width - std::countl_one(value << (64 - width));
    if (carry_from < end) {
      ++wide_step[carry_from];
      --wide_step[end];
    }
  }
  if (all_zero) return kAllZeroOrder;
  const auto count = static_cast<std::int64_t>(values.size());
  int best = 0;
  std::int64_t best_bits = 0;
  std::int64_t wide = 0;    // sum of bit_width(v + 2^order) over values wider than order
  std::int64_t narrow = 0;  // values no wider than order
  for (int order = 0; order < kOrders; ++order) {
    wide += wide_step[order];
    narrow += static_cast<std::int64_t>(width_count[order]);
    const std::int64_t k1 = order + 1;
    const std::int64_t bits = 2 * (wide + narrow * k1) - count * k1;
    if (order == 0 || bits < best_bits) {
      best_bits = bits;
      best = order;
    }
  }
  return best;
}

}  // namespace ricochet::proto::snapshot_layout
