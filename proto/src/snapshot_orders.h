#pragma once
/// Picks the Exp-Golomb order that writes a set of values in the fewest bits (the encoder writes
/// it into the stream's header; PROTOCOL.md Snapshots §orders).

#include <array>
#include <bit>
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

/// best_order over values given (and taken back) one at a time, each below 2^63 (every field
/// the codec writes is below 2^34): the same order, without keeping the values.
///
/// The order-k code of v takes 2 * bit_width(v + 2^k) - k - 1 bits. With w = bit_width(v): for
/// k >= w, v < 2^k and bit_width(v + 2^k) = k + 1; for k < w it is w, or w + 1 when bits w-1..k
/// of v are all ones (v + 2^k carries into bit w), that is when k >= w - (v's leading ones). So
/// each value adds w to the orders [0, w) and 1 more to [w - ones, w), kept as differences; the
/// totals of every order follow in one pass over the orders.
class OrderTally {
 public:
  void add(std::uint64_t value) { tally(value, 1); }
  /// Takes back a value added before.
  void remove(std::uint64_t value) { tally(value, -1); }
  /// best_order of the values added and not taken back.
  int best() const;

 private:
  static constexpr int kOrders = kMaxChosenOrder + 1;
  void tally(std::uint64_t value, int sign) {
    count_ += sign;
    const int width = std::bit_width(value);
    if (width < kOrders) width_count_[width] += sign;
    if (width == 0) return;
    nonzero_ += sign;
    const int end = width < kOrders ? width : kOrders;
    wide_step_[0] += sign * width;
    wide_step_[end] -= sign * width;
    const int carry_from = width - std::countl_one(value << (64 - width));
    if (carry_from < end) {
      wide_step_[carry_from] += sign;
      wide_step_[end] -= sign;
    }
  }
  std::array<std::int32_t, kOrders + 1> wide_step_{};    ///< differences of sum over wider values
  std::array<std::int32_t, kOrders + 1> width_count_{};  ///< values of bit_width w, w < kOrders
  std::int32_t count_ = 0;
  std::int32_t nonzero_ = 0;
};

}  // namespace ricochet::proto::snapshot_layout
