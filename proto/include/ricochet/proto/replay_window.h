#pragma once
/// The 256-entry replay window (PROTOCOL.md Game channel transport §replay): a packet is accepted
/// once, and never when it is 256 or more sequences older than the newest accepted one. The same
/// window gives the 16-bit ack and 32 ack bits this end puts in every packet it sends.

#include <array>
#include <cstdint>

#include "ricochet/proto/packet.h"

namespace ricochet::proto {

class ReplayWindow {
 public:
  static constexpr std::size_t kSize = 256;

  /// True when `sequence` was accepted before or is too old to tell.
  bool already_received(std::uint64_t sequence) const {
    if (!any_ || sequence > newest_) return false;
    const std::uint64_t behind = newest_ - sequence;
    return behind >= kSize || bit(behind);
  }
  /// Call only after the packet authenticated.
  void mark_received(std::uint64_t sequence) {
    if (!any_) {
      missing_ = sequence;  // the peer's sequences start at 0
      newest_ = sequence;
    } else if (sequence > newest_) {
      missing_ += sequence - newest_ - 1;
      slide(sequence - newest_);
      newest_ = sequence;
    } else {
      --missing_;  // a gap below the newest filled
      ++late_;
    }
    any_ = true;
    const std::uint64_t behind = newest_ - sequence;
    if (behind < kSize) received_[behind / 64] |= std::uint64_t{1} << (behind % 64);
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
    ack.ack_bits = static_cast<std::uint32_t>(received_[0] >> 1);
    return ack;
  }
  bool any_received() const { return any_; }
  std::uint64_t newest() const { return newest_; }

 private:
  static constexpr std::size_t kWords = kSize / 64;
  bool bit(std::uint64_t behind) const { return (received_[behind / 64] >> (behind % 64)) & 1; }
  /// The newest moves up by `by`: every bit moves `by` further behind it; older ones fall out.
  void slide(std::uint64_t by) {
    if (by >= kSize) {
      received_.fill(0);
      return;
    }
    const std::size_t words = by / 64;
    const unsigned bits = by % 64;
    for (std::size_t i = kWords; i-- > 0;) {
      std::uint64_t moved = 0;
      if (i >= words) {
        moved = received_[i - words] << bits;
        if (bits != 0 && i > words) moved |= received_[i - words - 1] >> (64 - bits);
      }
      received_[i] = moved;
    }
  }

  /// Bit k (word k / 64, bit k % 64): sequence newest_ - k was accepted. 32 bytes a connection,
  /// so a packet's replay check and its ack header touch one cache line.
  std::array<std::uint64_t, kWords> received_{};
  std::uint64_t newest_ = 0;
  bool any_ = false;
  std::uint64_t missing_ = 0;
  std::uint64_t late_ = 0;
};

}  // namespace ricochet::proto
