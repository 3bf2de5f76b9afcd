#pragma once
/// The small reliable-ordered message channel that rides on payload packets
/// (PROTOCOL.md Game channel transport §reliable). The sender keeps every message until a packet
/// carrying it is acked and resends it at most every resend interval; the receiver delivers in id
/// order, once, and buffers up to kWindow messages ahead of the next expected id. The sender has
/// at most a window of messages in flight; more wait behind them, unsent, until acks make room.

#include <cstdint>
#include <deque>
#include <optional>
#include <span>
#include <vector>

#include "ricochet/proto/clock.h"
#include "ricochet/proto/packet.h"

namespace ricochet::proto {

/// How a reliable message fares when its recipient falls behind (PROTOCOL.md §reliable).
enum class Delivery : std::uint8_t {
  /// Queued behind whatever is unacked and never dropped (kills, joins, the match's end): only
  /// a peer that acks none of max_queued messages loses its connection.
  MustArrive,
  /// Refused once the queue holds half a window (chat): a backlog of these never costs the
  /// recipient its connection, nor a must-arrive message its room in the window.
  Droppable,
};

class ReliableSender {
 public:
  /// `window` (1..256): messages in flight (sent, not yet acked) at most, the receiver's window.
  /// `max_queued` (window or more): messages held at most, in flight or waiting behind them.
  ReliableSender(std::size_t window, std::size_t max_queued);

  /// Queues `message`; false when refused: a Droppable one once window/2 messages (at least 1)
  /// are queued, a MustArrive one once max_queued are.
  bool push(std::span<const std::uint8_t> message, Delivery delivery = Delivery::MustArrive);
  /// Messages due (never sent, or last sent at least resend_us ago) among the window's oldest,
  /// oldest first, whose total size with their headers fits budget_bytes; at most 255. Marks
  /// them sent at `now`.
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
  /// The window's oldest, then the waiting; ids consecutive from queue_.front().id.
  std::deque<Pending> queue_;
  std::size_t window_;
  std::size_t max_queued_;
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
