#include "ricochet/proto/ack_window.h"

namespace ricochet::proto {

void SentPacketWindow::on_sent(std::uint64_t sequence, TimeUs now,
                               std::vector<std::uint16_t> reliable_ids) {
  Entry& entry = entries_[sequence % kSize];
  entry.sequence = sequence;
  entry.sent_at = now;
  entry.acked = false;
  entry.reliable_ids = std::move(reliable_ids);
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
  for (std::uint64_t i = 0; i < 32 && i < newest; ++i) {
    if (ack.ack_bits & (std::uint32_t{1} << i)) acknowledge(newest - 1 - i, now, acked_ids);
  }
}

bool SentPacketWindow::acked(std::uint64_t sequence) const {
  const Entry& entry = entries_[sequence % kSize];
  return entry.sequence == sequence && entry.acked;
}

void SentPacketWindow::acknowledge(std::uint64_t sequence, TimeUs now,
                                   std::vector<std::uint16_t>& acked_ids) {
  Entry& entry = entries_[sequence % kSize];
  if (entry.sequence != sequence || entry.acked) return;
  entry.acked = true;
  acked_ids.insert(acked_ids.end(), entry.reliable_ids.begin(), entry.reliable_ids.end());
  const TimeUs sample = now - entry.sent_at;
  rtt_us_ = rtt_us_ == 0 ? sample : rtt_us_ + (sample - rtt_us_) / 8;
}

}  // namespace ricochet::proto
