#pragma once
/// The datagrams an endpoint has queued for poll_transmit, in slots that keep their buffers.
///
/// A packet is written into the buffer its slot held before, and poll_transmit swaps buffers
/// with the caller's Transmit instead of moving one out: the caller's previous buffer comes back
/// into the slot. A socket layer that keeps its Transmits between flushes (DatagramSender) thus
/// sends a steady stream of packets without allocating: an allocation and a free fewer per
/// datagram sent, each of a buffer the kernel then copies from (tools/bench/results/server-io.md).

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "ricochet/proto/transmit.h"

namespace ricochet::proto {

class TransmitQueue {
 public:
  /// The buffer of a new datagram to `to`, emptied (its capacity is whatever the buffers that
  /// came back had: with reuse it settles at the largest packets').
  std::vector<std::uint8_t>& push(const Address& to) {
    Transmit& slot = next_slot(to);
    slot.bytes.clear();
    return slot.bytes;
  }
  /// A datagram already built elsewhere (handshakes, disconnects: rare).
  void push(const Address& to, std::vector<std::uint8_t> bytes) {
    next_slot(to).bytes = std::move(bytes);
  }
  /// The oldest datagram into `out`, whose previous buffer the queue keeps for a later one.
  bool pop(Transmit& out) {
    if (head_ == tail_) return false;
    Transmit& slot = slots_[head_++];
    out.to = slot.to;
    std::swap(out.bytes, slot.bytes);
    if (head_ == tail_) reset();
    return true;
  }
  bool empty() const { return head_ == tail_; }

 private:
  /// Slots kept when the queue empties: a packet for each of the most clients a server takes
  /// (GameServerConfig::max_clients ≤ 4096, one update's keep-alives), so that steady traffic
  /// never shrinks and regrows the queue; a larger burst (disconnect_all's copies) does not pin
  /// its memory.
  static constexpr std::size_t kSlotsKept = 4096;

  Transmit& next_slot(const Address& to) {
    if (tail_ == slots_.size()) slots_.emplace_back();
    Transmit& slot = slots_[tail_++];
    slot.to = to;
    return slot;
  }
  void reset() {
    head_ = tail_ = 0;
    if (slots_.size() > kSlotsKept) {
      slots_.resize(kSlotsKept);
      slots_.shrink_to_fit();
    }
  }

  std::vector<Transmit> slots_;
  std::size_t head_ = 0;  ///< the next to pop
  std::size_t tail_ = 0;  ///< one past the last pushed
};

}  // namespace ricochet::proto
