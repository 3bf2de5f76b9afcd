#include "ricochet/proto/ack_window.h"

#include <algorithm>
#include <bit>

namespace ricochet::proto {

void SentPacketWindow::on_sent(std::uint64_t sequence, TimeUs now,
                               std::vector<std::uint16_t> reliable_ids) {
  const std::size_t slot = sequence % kSize;
  entries_[slot] = {static_cast<std::uint32_t>(sequence), static_cast<std::uint32_t>(now)};
  set(awaiting_, slot);
  set(written_, slot);
  // What left the window can no longer be acked: its messages are the resender's business.
  std::erase_if(carried_, [&](const Carried& c) { return c.sequence + kSize <= sequence; });
  if (!reliable_ids.empty()) carried_.push_back({sequence, std::move(reliable_ids)});
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
  const std::size_t slot = sequence % kSize;
  return test(written_, slot) && !test(awaiting_, slot) &&
         entries_[slot].sequence_low == static_cast<std::uint32_t>(sequence);
}

void SentPacketWindow::acknowledge(std::uint64_t sequence, TimeUs now,
                                   std::vector<std::uint16_t>& acked_ids) {
  const std::size_t slot = sequence % kSize;
  if (!test(awaiting_, slot)) return;
  const Entry& entry = entries_[slot];
  if (entry.sequence_low != static_cast<std::uint32_t>(sequence)) return;
  clear(awaiting_, slot);
  if (!carried_.empty()) {
    const auto carried = std::find_if(carried_.begin(), carried_.end(),
                                      [&](const Carried& c) { return c.sequence == sequence; });
    if (carried != carried_.end()) {
      acked_ids.insert(acked_ids.end(), carried->reliable_ids.begin(), carried->reliable_ids.end());
      carried_.erase(carried);
    }
  }
  const std::uint32_t sample = static_cast<std::uint32_t>(now) - entry.sent_at_low;  // mod 2^32
  rtt_us_ = rtt_us_ == 0 ? sample : rtt_us_ + (sample - rtt_us_) / 8;
}

}  // namespace ricochet::proto
