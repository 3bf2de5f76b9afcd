#include "ricochet/proto/packet.h"

#include <algorithm>

#include "byte_io.h"
#include "ricochet/proto/connect_token.h"

namespace ricochet::proto {
namespace {

/// version | u64 protocol_id | u8 type: a packet's additional data (on the stack: it is built
/// for every packet sealed or opened).
std::array<std::uint8_t, kVersionBytes + 8 + 1> packet_ad(std::uint64_t protocol_id,
                                                          std::uint8_t type) {
  const VersionAndProtocol start = version_and_protocol(protocol_id);
  std::array<std::uint8_t, kVersionBytes + 8 + 1> ad;
  std::copy(start.begin(), start.end(), ad.begin());
  ad.back() = type;
  return ad;
}

/// Smallest body each encrypted type can have (the request is handled apart).
std::size_t min_body_bytes(PacketType type) {
  switch (type) {
    case PacketType::ConnectionRequest:
      return kConnectionRequestBytes;
    case PacketType::ConnectionDenied:
      return 1;
    case PacketType::Challenge:
    case PacketType::Response:
      return 8 + kChallengeTokenBytes;
    case PacketType::KeepAlive:
      return kAckHeaderBytes;
    case PacketType::Payload:
      return kPayloadFixedBytes;
    case PacketType::Disconnect:
      return kAckHeaderBytes + 1;
  }
  return 0;
}

AckHeader read_ack(ByteReader& reader) {
  AckHeader ack;
  ack.ack = reader.u16();
  ack.ack_bits = reader.u32();
  return ack;
}

void write_ack(ByteWriter& writer, const AckHeader& ack) {
  writer.u16(ack.ack);
  writer.u32(ack.ack_bits);
}

template <class T>
Parsed<T> refused(DropReason reason) {
  Parsed<T> out;
  out.error = reason;
  return out;
}

std::optional<DisconnectReason> disconnect_reason_from(std::uint8_t byte) {
  if (byte >= kDisconnectReasonCount) return std::nullopt;
  return static_cast<DisconnectReason>(byte);
}

}  // namespace

VersionAndProtocol version_and_protocol(std::uint64_t protocol_id) {
  VersionAndProtocol out;
  std::copy(kVersionInfo.begin(), kVersionInfo.end(), out.begin());
  for (std::size_t i = 0; i < 8; ++i) {
    out[kVersionBytes + i] = static_cast<std::uint8_t>(protocol_id >> (8 * i));  // little endian
  }
  return out;
}

std::string_view name(PacketType type) {
  switch (type) {
    case PacketType::ConnectionRequest:
      return "connection_request";
    case PacketType::ConnectionDenied:
      return "connection_denied";
    case PacketType::Challenge:
      return "challenge";
    case PacketType::Response:
      return "response";
    case PacketType::KeepAlive:
      return "keep_alive";
    case PacketType::Payload:
      return "payload";
    case PacketType::Disconnect:
      return "disconnect";
  }
  return "unknown";
}

std::vector<std::uint8_t> write_connection_request(std::uint64_t protocol_id,
                                                   std::span<const std::uint8_t> connect_token) {
  std::vector<std::uint8_t> out;
  out.reserve(kConnectionRequestBytes);
  ByteWriter writer(out);
  writer.u8(static_cast<std::uint8_t>(PacketType::ConnectionRequest));
  writer.bytes(kVersionInfo);
  writer.u64(protocol_id);
  writer.u16(static_cast<std::uint16_t>(connect_token.size()));
  writer.bytes(connect_token);
  out.resize(kConnectionRequestBytes, 0);
  return out;
}

Parsed<ConnectionRequest> read_connection_request(std::span<const std::uint8_t> datagram) {
  if (datagram.size() < kConnectionRequestBytes) {
    return refused<ConnectionRequest>(DropReason::Truncated);
  }
  if (datagram.size() > kConnectionRequestBytes) {
    return refused<ConnectionRequest>(DropReason::Oversized);
  }
  ByteReader reader(datagram);
  if (reader.u8() != static_cast<std::uint8_t>(PacketType::ConnectionRequest)) {
    return refused<ConnectionRequest>(DropReason::Malformed);
  }
  auto version = reader.bytes(kVersionBytes);
  if (!std::equal(version.begin(), version.end(), kVersionInfo.begin())) {
    return refused<ConnectionRequest>(DropReason::WrongVersion);
  }
  Parsed<ConnectionRequest> out;
  out.value.protocol_id = reader.u64();
  const std::size_t token_bytes = reader.u16();
  if (token_bytes != kConnectTokenBytes) return refused<ConnectionRequest>(DropReason::Malformed);
  auto token = reader.bytes(token_bytes);
  const auto padding = reader.rest();
  if (std::any_of(padding.begin(), padding.end(), [](std::uint8_t byte) { return byte != 0; })) {
    return refused<ConnectionRequest>(DropReason::Malformed);
  }
  out.value.connect_token.assign(token.begin(), token.end());
  return out;
}

Parsed<EncryptedHeader> read_encrypted_header(std::span<const std::uint8_t> datagram) {
  if (datagram.empty()) return refused<EncryptedHeader>(DropReason::Empty);
  if (datagram.size() > kMaxDatagramBytes) return refused<EncryptedHeader>(DropReason::Oversized);
  const std::uint8_t type_byte = datagram[0];
  if (type_byte == 0 || type_byte >= kPacketTypeCount) {
    return refused<EncryptedHeader>(DropReason::Malformed);
  }
  Parsed<EncryptedHeader> out;
  out.value.type = static_cast<PacketType>(type_byte);
  if (datagram.size() < kEncryptedHeaderBytes + min_body_bytes(out.value.type) + kMacBytes) {
    return refused<EncryptedHeader>(DropReason::Truncated);
  }
  ByteReader reader(datagram.subspan(1, 8));
  out.value.sequence = reader.u64();
  return out;
}

std::vector<std::uint8_t> seal_packet(PacketType type, std::uint64_t sequence,
                                      std::uint64_t protocol_id, const Key& key,
                                      std::span<const std::uint8_t> body) {
  std::vector<std::uint8_t> out;
  out.reserve(kEncryptedHeaderBytes + body.size() + kMacBytes);
  begin_packet(type, sequence, out);
  out.insert(out.end(), body.begin(), body.end());
  seal_packet_in_place(protocol_id, key, out);
  return out;
}

void begin_packet(PacketType type, std::uint64_t sequence, std::vector<std::uint8_t>& packet) {
  packet.clear();
  ByteWriter writer(packet);
  writer.u8(static_cast<std::uint8_t>(type));
  writer.u64(sequence);
}

void seal_packet_in_place(std::uint64_t protocol_id, const Key& key,
                          std::vector<std::uint8_t>& packet) {
  ByteReader reader(std::span<const std::uint8_t>(packet).subspan(1, 8));
  const std::uint64_t sequence = reader.u64();
  const auto ad = packet_ad(protocol_id, packet[0]);
  const std::size_t body_bytes = packet.size() - kEncryptedHeaderBytes;
  packet.resize(packet.size() + kMacBytes);
  seal_chacha_in_place(std::span(packet).subspan(kEncryptedHeaderBytes, body_bytes), ad, sequence,
                       key, packet.data() + kEncryptedHeaderBytes + body_bytes);
}

bool open_packet(std::span<const std::uint8_t> datagram, std::uint64_t protocol_id, const Key& key,
                 std::vector<std::uint8_t>& body) {
  if (datagram.size() < kEncryptedHeaderBytes + kMacBytes) return false;
  ByteReader reader(datagram.subspan(1, 8));
  const std::uint64_t sequence = reader.u64();
  const auto ad = packet_ad(protocol_id, datagram[0]);
  return open_chacha(datagram.subspan(kEncryptedHeaderBytes), ad, sequence, key, body);
}

std::vector<std::uint8_t> write_challenge_body(const ChallengeBody& body) {
  std::vector<std::uint8_t> out;
  ByteWriter writer(out);
  writer.u64(body.challenge_sequence);
  writer.bytes(body.challenge_token);
  return out;
}

Parsed<ChallengeBody> read_challenge_body(std::span<const std::uint8_t> body) {
  if (body.size() != 8 + kChallengeTokenBytes) return refused<ChallengeBody>(DropReason::Malformed);
  ByteReader reader(body);
  Parsed<ChallengeBody> out;
  out.value.challenge_sequence = reader.u64();
  reader.copy_to(out.value.challenge_token);
  return out;
}

std::vector<std::uint8_t> write_denied_body(DisconnectReason reason) {
  return {static_cast<std::uint8_t>(reason)};
}

Parsed<DisconnectReason> read_denied_body(std::span<const std::uint8_t> body) {
  if (body.size() != 1) return refused<DisconnectReason>(DropReason::Malformed);
  auto reason = disconnect_reason_from(body[0]);
  if (!reason) return refused<DisconnectReason>(DropReason::Malformed);
  return {*reason, std::nullopt};
}

std::vector<std::uint8_t> write_keep_alive_body(const AckHeader& ack) {
  std::vector<std::uint8_t> out;
  ByteWriter writer(out);
  write_ack(writer, ack);
  return out;
}

Parsed<AckHeader> read_keep_alive_body(std::span<const std::uint8_t> body) {
  if (body.size() != kAckHeaderBytes) return refused<AckHeader>(DropReason::Malformed);
  ByteReader reader(body);
  return {read_ack(reader), std::nullopt};
}

std::vector<std::uint8_t> write_disconnect_body(const DisconnectBody& body) {
  std::vector<std::uint8_t> out;
  ByteWriter writer(out);
  write_ack(writer, body.ack);
  writer.u8(static_cast<std::uint8_t>(body.reason));
  return out;
}

Parsed<DisconnectBody> read_disconnect_body(std::span<const std::uint8_t> body) {
  if (body.size() != kAckHeaderBytes + 1) return refused<DisconnectBody>(DropReason::Malformed);
  ByteReader reader(body);
  Parsed<DisconnectBody> out;
  out.value.ack = read_ack(reader);
  auto reason = disconnect_reason_from(reader.u8());
  if (!reason) return refused<DisconnectBody>(DropReason::Malformed);
  out.value.reason = *reason;
  return out;
}

std::vector<std::uint8_t> write_payload_body(const PayloadBody& body) {
  std::vector<std::uint8_t> out;
  append_payload_body(body.ack, body.reliable, body.unreliable, out);
  return out;
}

void append_payload_body(const AckHeader& ack, std::span<const ReliableMessage> reliable,
                         std::span<const std::uint8_t> unreliable, std::vector<std::uint8_t>& out) {
  ByteWriter writer(out);
  write_ack(writer, ack);
  writer.u8(static_cast<std::uint8_t>(reliable.size()));
  for (const ReliableMessage& message : reliable) {
    writer.u16(message.id);
    writer.u16(static_cast<std::uint16_t>(message.bytes.size()));
    writer.bytes(message.bytes);
  }
  writer.bytes(unreliable);
}

namespace {

/// Reads a payload body up to its unreliable bytes, which are left in `reader`.
Parsed<PayloadBody> read_payload_head(ByteReader& reader) {
  Parsed<PayloadBody> out;
  out.value.ack = read_ack(reader);
  const std::size_t count = reader.u8();
  if (reader.failed()) return refused<PayloadBody>(DropReason::Truncated);
  for (std::size_t i = 0; i < count; ++i) {
    ReliableMessage message;
    message.id = reader.u16();
    const std::size_t length = reader.u16();
    if (reader.failed()) return refused<PayloadBody>(DropReason::Truncated);
    if (length == 0 || length > kMaxReliableMessageBytes) {
      return refused<PayloadBody>(DropReason::Malformed);
    }
    auto bytes = reader.bytes(length);
    if (reader.failed()) return refused<PayloadBody>(DropReason::Truncated);
    message.bytes.assign(bytes.begin(), bytes.end());
    out.value.reliable.push_back(std::move(message));
  }
  return out;
}

}  // namespace

Parsed<PayloadBody> read_payload_body(std::span<const std::uint8_t> body) {
  ByteReader reader(body);
  Parsed<PayloadBody> out = read_payload_head(reader);
  if (!out.ok()) return out;
  auto rest = reader.rest();
  out.value.unreliable.assign(rest.begin(), rest.end());
  return out;
}

Parsed<PayloadBody> read_payload_body(std::vector<std::uint8_t>&& body) {
  ByteReader reader(body);
  Parsed<PayloadBody> out = read_payload_head(reader);
  if (!out.ok()) return out;
  const std::size_t head_bytes = body.size() - reader.remaining();
  body.erase(body.begin(), body.begin() + static_cast<std::ptrdiff_t>(head_bytes));
  out.value.unreliable = std::move(body);
  return out;
}

}  // namespace ricochet::proto
