#include "ricochet/proto/ack_window.h"

#include <bit>

namespace ricochet::proto {

void SentPacketWindow::on_sent(std::uint64_t sequence, TimeUs now,
                               std::vector<std::uint16_t> reliable_ids) {
  const std::size_t slot = sequence % kSize;
  Entry& entry = entries_[slot];
  entry.sequence = sequence;
  entry.sent_at = now;
  entry.reliable_ids = std::move(reliable_ids);
  awaiting_[slot / 64] |= std::uint64_t{1} << (slot % 64);
}

void SentPacketWindow::on_ack(const AckHeader& ack, std::uint64_t next_sequence, TimeUs now,
                              std::vector<std::uint16_t>& acked_ids) {
  if (next_sequence == 0) return;  // nothing sent: an ack of nothing
  // The newest sent sequence whose low 16 bits equal the ack.
  std::uint64_t newest = ((next_sequence - 1) & ~std::uint64_t{0xFFFF}) | ack.ack;
  if (newest >= next_sequence) {
    if (newest < 0x10000) return;  // refers to a sequence never sent
    newest -= 0x10000;
  }
  acknowledge(newest, now, acked_ids);
  for (std::uint32_t bits = ack.ack_bits; bits != 0; bits &= bits - 1) {
    const std::uint64_t i = static_cast<std::uint64_t>(std::countr_zero(bits));
    if (i >= newest) break;
    acknowledge(newest - 1 - i, now, acked_ids);
  }
}

bool SentPacketWindow::acked(std::uint64_t sequence) const {
  return entries_[sequence % kSize].sequence == sequence && !awaiting(sequence % kSize);
}

void SentPacketWindow::acknowledge(std::uint64_t sequence, TimeUs now,
                                   std::vector<std::uint16_t>& acked_ids) {
  const std::size_t slot = sequence % kSize;
  if (!awaiting(slot)) return;
  Entry& entry = entries_[slot];
  if (entry.sequence != sequence) return;
  awaiting_[slot / 64] &= ~(std::uint64_t{1} << (slot % 64));
  acked_ids.insert(acked_ids.end(), entry.reliable_ids.begin(), entry.reliable_ids.end());
  const TimeUs sample = now - entry.sent_at;
  rtt_us_ = rtt_us_ == 0 ? sample : rtt_us_ + (sample - rtt_us_) / 8;
}

}  // namespace ricochet::proto
