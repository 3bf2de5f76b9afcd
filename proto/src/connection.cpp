#include "connection.h"

namespace ricochet::proto {

Connection::Connection(std::uint64_t protocol_id, const Key& send_key, const Key& receive_key,
                       ConnectionTiming timing, TimeUs now)
    : protocol_id_(protocol_id),
      send_key_(send_key),
      receive_key_(receive_key),
      timing_(timing),
      sender_(timing.max_reliable_pending, timing.max_reliable_queued),
      last_sent_(now),
      last_received_(now) {}

std::optional<DropReason> Connection::open(const EncryptedHeader& header,
                                           std::span<const std::uint8_t> datagram,
                                           std::vector<std::uint8_t>& body, TimeUs now) {
  if (replay_.already_received(header.sequence)) return DropReason::Replayed;
  if (!open_packet(datagram, protocol_id_, receive_key_, body)) return DropReason::ForgedMac;
  replay_.mark_received(header.sequence);
  last_received_ = now;
  return std::nullopt;
}

std::uint64_t Connection::take_sequence(TimeUs now) {
  const std::uint64_t sequence = next_sequence_++;
  sent_.on_sent(sequence, now, std::move(pending_ids_));
  pending_ids_.clear();
  last_sent_ = now;
  return sequence;
}

std::vector<std::uint8_t> Connection::seal(PacketType type, std::span<const std::uint8_t> body,
                                           TimeUs now) {
  return seal_packet(type, take_sequence(now), protocol_id_, send_key_, body);
}

std::vector<std::uint8_t> Connection::make_keep_alive(TimeUs now) {
  return seal(PacketType::KeepAlive, write_keep_alive_body(replay_.ack_header()), now);
}

std::vector<std::uint8_t> Connection::make_payload(std::span<const std::uint8_t> unreliable,
                                                   TimeUs now) {
  std::vector<std::uint8_t> packet;
  make_payload(unreliable, now, packet);
  return packet;
}

void Connection::make_payload(std::span<const std::uint8_t> unreliable, TimeUs now,
                              std::vector<std::uint8_t>& packet) {
  const AckHeader ack = replay_.ack_header();
  const std::size_t budget = kMaxBodyBytes - kPayloadFixedBytes - unreliable.size();
  const std::vector<ReliableMessage> reliable =
      sender_.take_due(now, timing_.reliable_resend_us, budget);
  std::size_t reliable_bytes = 0;
  for (const ReliableMessage& message : reliable) {
    pending_ids_.push_back(message.id);
    reliable_bytes += kReliableMessageHeaderBytes + message.bytes.size();
  }
  // Header, body and tag in one buffer, the body encrypted where it was written.
  packet.reserve(kEncryptedHeaderBytes + kPayloadFixedBytes + reliable_bytes + unreliable.size() +
                 kMacBytes);
  begin_packet(PacketType::Payload, take_sequence(now), packet);
  append_payload_body(ack, reliable, unreliable, packet);
  seal_packet_in_place(protocol_id_, send_key_, packet);
}

std::vector<std::uint8_t> Connection::make_disconnect(DisconnectReason reason, TimeUs now) {
  return seal(PacketType::Disconnect, write_disconnect_body({replay_.ack_header(), reason}), now);
}

void Connection::on_ack(const AckHeader& ack, TimeUs now) {
  std::vector<std::uint16_t> acked;
  sent_.on_ack(ack, next_sequence_, now, acked);
  for (std::uint16_t id : acked) sender_.acknowledge(id);
}

bool Connection::on_reliable(const std::vector<ReliableMessage>& messages) {
  bool all_in_window = true;
  for (const ReliableMessage& message : messages) {
    if (receiver_.receive(message) == ReliableReceiver::Outcome::OutOfWindow) all_in_window = false;
  }
  return all_in_window;
}

}  // namespace ricochet::proto
