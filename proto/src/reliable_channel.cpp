#include "ricochet/proto/reliable_channel.h"

#include <algorithm>

namespace ricochet::proto {

ReliableSender::ReliableSender(std::size_t window, std::size_t max_queued)
    : window_(std::clamp<std::size_t>(window, 1, ReliableReceiver::kWindow)),
      max_queued_(std::max(max_queued, window_)) {}

bool ReliableSender::push(std::span<const std::uint8_t> message, Delivery delivery) {
  const std::size_t cap =
      delivery == Delivery::Droppable ? std::max<std::size_t>(window_ / 2, 1) : max_queued_;
  if (queue_.size() >= cap) return false;
  Pending pending;
  pending.id = next_id_++;
  pending.bytes.assign(message.begin(), message.end());
  queue_.push_back(std::move(pending));
  return true;
}

std::vector<ReliableMessage> ReliableSender::take_due(TimeUs now, TimeUs resend_us,
                                                      std::size_t budget_bytes) {
  std::vector<ReliableMessage> out;
  // Only the window's oldest: the receiver refuses ids further ahead of the oldest unacked.
  const auto window_end =
      queue_.begin() + static_cast<std::ptrdiff_t>(std::min(window_, queue_.size()));
  for (auto it = queue_.begin(); it != window_end; ++it) {
    Pending& pending = *it;
    if (out.size() == 255) break;
    if (pending.acked || (pending.last_sent && now - *pending.last_sent < resend_us)) continue;
    const std::size_t cost = kReliableMessageHeaderBytes + pending.bytes.size();
    if (cost > budget_bytes) break;  // keep order: a later message must not overtake
    budget_bytes -= cost;
    if (pending.last_sent) ++resends_;
    pending.last_sent = now;
    out.push_back({pending.id, pending.bytes});
  }
  return out;
}

bool ReliableSender::has_due(TimeUs now, TimeUs resend_us) const {
  const auto window_end =
      queue_.begin() + static_cast<std::ptrdiff_t>(std::min(window_, queue_.size()));
  return std::any_of(queue_.begin(), window_end, [&](const Pending& pending) {
    return !pending.acked && (!pending.last_sent || now - *pending.last_sent >= resend_us);
  });
}

void ReliableSender::acknowledge(std::uint16_t id) {
  if (queue_.empty()) return;
  const std::uint16_t offset = static_cast<std::uint16_t>(id - queue_.front().id);
  if (offset >= queue_.size()) return;  // already acked and gone, or never sent
  queue_[offset].acked = true;
  while (!queue_.empty() && queue_.front().acked) queue_.pop_front();
}

ReliableReceiver::Outcome ReliableReceiver::receive(const ReliableMessage& message) {
  const std::uint16_t ahead = static_cast<std::uint16_t>(message.id - next_id_);
  if (ahead >= 0x8000) return Outcome::Duplicate;  // behind the next expected id: delivered
  if (ahead >= kWindow) return Outcome::OutOfWindow;
  auto& slot = window_[message.id % kWindow];
  if (slot) return Outcome::Duplicate;
  slot = message.bytes;
  ++buffered_;
  return Outcome::Accepted;
}

bool ReliableReceiver::pop(std::vector<std::uint8_t>& out) {
  if (buffered_ == 0) return false;
  auto& slot = window_[next_id_ % kWindow];
  if (!slot) return false;
  out = std::move(*slot);
  slot.reset();
  --buffered_;
  ++next_id_;
  return true;
}

}  // namespace ricochet::proto
