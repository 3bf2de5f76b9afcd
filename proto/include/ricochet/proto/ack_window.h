#pragma once
/// What this end sent, so that the peer's acks (16-bit ack + 32 bits, PROTOCOL.md Game channel
/// transport §acks) tell which packets arrived, which reliable messages they carried, and the round
/// trip.

#include <array>
#include <cstdint>
#include <vector>

#include "ricochet/proto/clock.h"
#include "ricochet/proto/packet.h"

namespace ricochet::proto {

class SentPacketWindow {
 public:
  static constexpr std::size_t kSize = 256;

  /// `reliable_ids`: the reliable messages the packet carried.
  void on_sent(std::uint64_t sequence, TimeUs now, std::vector<std::uint16_t> reliable_ids);
  /// `next_sequence`: the sequence this end will send next (the ack refers to an earlier one).
  /// Appends the reliable ids of packets acknowledged for the first time to `acked_ids`.
  void on_ack(const AckHeader& ack, std::uint64_t next_sequence, TimeUs now,
              std::vector<std::uint16_t>& acked_ids);
  /// True once `sequence` was acknowledged (false when unknown or too old).
  bool acked(std::uint64_t sequence) const;
  /// Smoothed round trip from acks of packets acked for the first time, 0 before any, in µs.
  TimeUs rtt_us() const { return rtt_us_; }

 private:
  /// 8 bytes, so a cache line holds 8 packets' entries: a connection's window is 2 KiB, and the
  /// stream of sends and acks walks it a line per 8 packets. The low 32 bits of the sequence tell
  /// a slot's packets apart (they differ by multiples of kSize, far below 2^32), and of the send
  /// time give round trips below 71 minutes exactly (the difference is taken modulo 2^32).
  struct Entry {
    std::uint32_t sequence_low = 0;
    std::uint32_t sent_at_low = 0;
  };
  /// The reliable messages a packet carried (rare: events, not snapshots).
  struct Carried {
    std::uint64_t sequence = 0;
    std::vector<std::uint16_t> reliable_ids;
  };
  static constexpr std::size_t kWords = kSize / 64;
  using Bits = std::array<std::uint64_t, kWords>;
  static bool test(const Bits& bits, std::size_t slot) {
    return (bits[slot / 64] >> (slot % 64)) & 1;
  }
  static void set(Bits& bits, std::size_t slot) {
    bits[slot / 64] |= std::uint64_t{1} << (slot % 64);
  }
  static void clear(Bits& bits, std::size_t slot) {
    bits[slot / 64] &= ~(std::uint64_t{1} << (slot % 64));
  }
  void acknowledge(std::uint64_t sequence, TimeUs now, std::vector<std::uint16_t>& acked_ids);

  std::array<Entry, kSize> entries_{};
  /// Bit s: entries_[s] was sent and not yet acked. An ack repeats 33 packets' fates, nearly
  /// all known already; these 32 bytes answer for them without touching the entries.
  Bits awaiting_{};
  Bits written_{};                ///< bit s: entries_[s] holds a packet
  std::vector<Carried> carried_;  ///< of packets in the window not yet acked, oldest first
  TimeUs rtt_us_ = 0;
};

}  // namespace ricochet::proto
