#pragma once
/// One end of an established (or establishing) session, shared by GameServer and GameClient:
/// the send sequence and key, the replay window and receive key, the acks, the reliable channel,
/// the keep-alive and silence timers. Knows no addresses and no states; the endpoints do.

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "ricochet/proto/ack_window.h"
#include "ricochet/proto/packet.h"
#include "ricochet/proto/reliable_channel.h"
#include "ricochet/proto/replay_window.h"

namespace ricochet::proto {

struct ConnectionTiming {
  TimeUs timeout_us = 5 * kMicrosPerSecond;      ///< silence after which the peer is gone
  TimeUs keep_alive_us = 100 * kMicrosPerMilli;  ///< send something at least this often
  TimeUs reliable_resend_us = 100 * kMicrosPerMilli;
  std::size_t max_reliable_pending = 256;  ///< in flight: ReliableSender's window (1..256)
  std::size_t max_reliable_queued = 256;   ///< held: in flight or waiting (ReliableSender)
};

class Connection {
 public:
  Connection(std::uint64_t protocol_id, const Key& send_key, const Key& receive_key,
             ConnectionTiming timing, TimeUs now);

  /// Replay check, then decryption; on success the sequence counts as received and the silence
  /// timer restarts. `header` from read_encrypted_header.
  std::optional<DropReason> open(const EncryptedHeader& header,
                                 std::span<const std::uint8_t> datagram,
                                 std::vector<std::uint8_t>& body, TimeUs now);
  /// Seals `body` under the next sequence.
  std::vector<std::uint8_t> seal(PacketType type, std::span<const std::uint8_t> body, TimeUs now);

  std::vector<std::uint8_t> make_keep_alive(TimeUs now);
  /// A payload packet with `unreliable` (≤ kMaxUnreliableBytes) and the reliable messages due
  /// that fit beside it.
  std::vector<std::uint8_t> make_payload(std::span<const std::uint8_t> unreliable, TimeUs now);
  /// The same, written into `packet` (emptied first; a buffer with room allocates nothing).
  void make_payload(std::span<const std::uint8_t> unreliable, TimeUs now,
                    std::vector<std::uint8_t>& packet);
  std::vector<std::uint8_t> make_disconnect(DisconnectReason reason, TimeUs now);

  /// The peer's ack of this end's packets: acknowledges the reliable messages they carried.
  void on_ack(const AckHeader& ack, TimeUs now);
  /// Queues the reliable messages of a received payload; delivered in order by pop_reliable.
  /// False when one was too far ahead of the window (the rest are still taken).
  bool on_reliable(const std::vector<ReliableMessage>& messages);
  bool pop_reliable(std::vector<std::uint8_t>& out) { return receiver_.pop(out); }
  bool queue_reliable(std::span<const std::uint8_t> message, Delivery delivery) {
    return sender_.push(message, delivery);
  }

  bool reliable_due(TimeUs now) const { return sender_.has_due(now, timing_.reliable_resend_us); }
  bool keep_alive_due(TimeUs now) const { return now - last_sent_ >= timing_.keep_alive_us; }
  bool timed_out(TimeUs now) const { return now - last_received_ >= timing_.timeout_us; }
  std::uint64_t reliable_resends() const { return sender_.resends(); }
  TimeUs rtt_us() const { return sent_.rtt_us(); }
  /// The peer's sequences accepted so far (ReplayWindow::missing and late).
  const ReplayWindow& received() const { return replay_; }
  std::size_t reliable_pending() const { return sender_.pending(); }

 private:
  /// The sequence of the packet being sent now, recorded as sent with pending_ids_.
  std::uint64_t take_sequence(TimeUs now);

  std::uint64_t protocol_id_;
  Key send_key_;
  Key receive_key_;
  ConnectionTiming timing_;
  std::uint64_t next_sequence_ = 0;
  ReplayWindow replay_;
  SentPacketWindow sent_;
  ReliableSender sender_;
  ReliableReceiver receiver_;
  TimeUs last_sent_;
  TimeUs last_received_;
  std::vector<std::uint16_t> pending_ids_;  ///< ids of the reliable messages in the next packet
};

}  // namespace ricochet::proto
