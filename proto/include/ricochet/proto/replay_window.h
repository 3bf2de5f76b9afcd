#pragma once
/// The 256-entry replay window (PROTOCOL.md Game channel transport §replay): a packet is accepted
/// once, and never when it is 256 or more sequences older than the newest accepted one. The same
/// window gives the 16-bit ack and 32 ack bits this end puts in every packet it sends.

#include <array>
#include <cstdint>
#include <limits>

#include "ricochet/proto/packet.h"

namespace ricochet::proto {

class ReplayWindow {
 public:
  static constexpr std::size_t kSize = 256;

  /// True when `sequence` was accepted before or is too old to tell.
  bool already_received(std::uint64_t sequence) const {
    if (!any_) return false;
    if (sequence + kSize <= newest_) return true;
    return slots_[sequence % kSize] == sequence;
  }
  /// Call only after the packet authenticated.
  void mark_received(std::uint64_t sequence) {
    if (!any_) {
      missing_ = sequence;  // the peer's sequences start at 0
    } else if (sequence > newest_) {
      missing_ += sequence - newest_ - 1;
    } else {
      --missing_;  // a gap below the newest filled
      ++late_;
    }
    if (!any_ || sequence > newest_) newest_ = sequence;
    any_ = true;
    slots_[sequence % kSize] = sequence;
  }
  /// Sequences below the newest accepted one never accepted: lost on the way, too late for the
  /// window, or still on their way. Every packet the peer sends takes the next sequence, so
  /// missing() / (newest() + 1) is the link's loss towards this end, whatever the packets held.
  std::uint64_t missing() const { return missing_; }
  /// Packets accepted after a newer one (reordered or delayed on the way).
  std::uint64_t late() const { return late_; }
  /// Ack of the newest accepted sequence; bit i set when newest - 1 - i was accepted.
  AckHeader ack_header() const {
    AckHeader ack;
    if (!any_) return ack;
    ack.ack = static_cast<std::uint16_t>(newest_);
    for (std::uint64_t i = 0; i < 32 && i < newest_; ++i) {
      const std::uint64_t sequence = newest_ - 1 - i;
      if (slots_[sequence % kSize] == sequence) ack.ack_bits |= std::uint32_t{1} << i;
    }
    return ack;
  }
  bool any_received() const { return any_; }
  std::uint64_t newest() const { return newest_; }

 private:
  static constexpr std::uint64_t kEmpty = std::numeric_limits<std::uint64_t>::max();
  std::array<std::uint64_t, kSize> slots_ = [] {
    std::array<std::uint64_t, kSize> slots;
    slots.fill(kEmpty);
    return slots;
  }();
  std::uint64_t newest_ = 0;
  bool any_ = false;
  std::uint64_t missing_ = 0;
  std::uint64_t late_ = 0;
};

}  // namespace ricochet::proto
