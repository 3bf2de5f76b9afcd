#pragma once
/// The small reliable-ordered message channel that rides on payload packets
/// (PROTOCOL.md Game channel transport §reliable). The sender keeps every message until a packet
/// carrying it is acked and resends it at most every resend interval; the receiver delivers in id
/// order, once, and buffers up to kWindow messages ahead of the next expected id.

#include <cstdint>
#include <deque>
#include <optional>
#include <span>
#include <vector>

#include "ricochet/proto/clock.h"
#include "ricochet/proto/packet.h"

namespace ricochet::proto {

class ReliableSender {
 public:
  /// `max_pending` (1..256): messages sent and not yet acked; pushing one more fails.
  explicit ReliableSender(std::size_t max_pending);

  /// False when the queue already holds max_pending messages.
  bool push(std::span<const std::uint8_t> message);
  /// Messages due (never sent, or last sent at least resend_us ago), oldest first, whose total
  /// size with their headers fits budget_bytes; at most 255. Marks them sent at `now`.
  std::vector<ReliableMessage> take_due(TimeUs now, TimeUs resend_us, std::size_t budget_bytes);
  bool has_due(TimeUs now, TimeUs resend_us) const;
  void acknowledge(std::uint16_t id);
  std::size_t pending() const { return queue_.size(); }
  /// Messages sent again because no ack came within the resend interval.
  std::uint64_t resends() const { return resends_; }

 private:
  struct Pending {
    std::uint16_t id = 0;
    std::vector<std::uint8_t> bytes;
    std::optional<TimeUs> last_sent;
    bool acked = false;
  };
  std::deque<Pending> queue_;  ///< ids consecutive from queue_.front().id
  std::size_t max_pending_;
  std::uint16_t next_id_ = 0;
  std::uint64_t resends_ = 0;
};

class ReliableReceiver {
 public:
  static constexpr std::size_t kWindow = 256;
  enum class Outcome { Accepted, Duplicate, OutOfWindow };

  Outcome receive(const ReliableMessage& message);
  /// The next message in order, if it has arrived.
  bool pop(std::vector<std::uint8_t>& out);

 private:
  std::vector<std::optional<std::vector<std::uint8_t>>> window_ =
      std::vector<std::optional<std::vector<std::uint8_t>>>(kWindow);
  std::size_t buffered_ = 0;  ///< filled slots of window_: none on nearly every packet
  std::uint16_t next_id_ = 0;
};

}  // namespace ricochet::proto
