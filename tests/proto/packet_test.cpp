#include "ricochet/proto/packet.h"

#include <gtest/gtest.h>

#include <set>
#include <string_view>

#include "ricochet/proto/connect_token.h"

namespace ricochet::proto::packet_test {
namespace {

const Key kKey = [] {
  Key key{};
  key[0] = 7;
  return key;
}();
constexpr std::uint64_t kProtocol = 42;

std::vector<std::uint8_t> some_token() {
  return std::vector<std::uint8_t>(kConnectTokenBytes, 0x5A);
}

TEST(ConnectionRequest, IsPaddedToTheLargestDatagramAndRoundTrips) {
  const auto bytes = write_connection_request(kProtocol, some_token());
  EXPECT_EQ(bytes.size(), kMaxDatagramBytes);
  auto parsed = read_connection_request(bytes);
  ASSERT_TRUE(parsed.ok());
  EXPECT_EQ(parsed.value.protocol_id, kProtocol);
  EXPECT_EQ(parsed.value.connect_token, some_token());
}

TEST(ConnectionRequest, RefusesWrongSizesVersionAndTokenLength) {
  auto bytes = write_connection_request(kProtocol, some_token());
  auto short_bytes = bytes;
  short_bytes.pop_back();
  EXPECT_EQ(read_connection_request(short_bytes).error, DropReason::Truncated);
  auto long_bytes = bytes;
  long_bytes.push_back(0);
  EXPECT_EQ(read_connection_request(long_bytes).error, DropReason::Oversized);
  auto version = bytes;
  version[1] ^= 1;
  EXPECT_EQ(read_connection_request(version).error, DropReason::WrongVersion);
  auto token_length = bytes;
  token_length[1 + kVersionBytes + 8] = 3;
  EXPECT_EQ(read_connection_request(token_length).error, DropReason::Malformed);
}

TEST(ConnectionRequest, RefusesPaddingThatIsNotZero) {
  const auto bytes = write_connection_request(kProtocol, some_token());
  const std::size_t padding_at = 1 + kVersionBytes + 8 + 2 + kConnectTokenBytes;
  ASSERT_LT(padding_at, bytes.size());
  for (std::size_t at : {padding_at, (padding_at + bytes.size()) / 2, bytes.size() - 1}) {
    auto padded = bytes;
    padded[at] = 0x01;
    EXPECT_EQ(read_connection_request(padded).error, DropReason::Malformed) << "byte " << at;
  }
}

TEST(EncryptedPacket, SealsAndOpensWithTheSameKeyAndProtocolOnly) {
  const std::vector<std::uint8_t> body = {1, 2, 3, 4, 5, 6, 7};
  const auto packet = seal_packet(PacketType::KeepAlive, 77, kProtocol, kKey, body);
  EXPECT_EQ(packet.size(), kEncryptedHeaderBytes + body.size() + kMacBytes);
  auto header = read_encrypted_header(packet);
  ASSERT_TRUE(header.ok());
  EXPECT_EQ(header.value.type, PacketType::KeepAlive);
  EXPECT_EQ(header.value.sequence, 77u);
  std::vector<std::uint8_t> opened;
  ASSERT_TRUE(open_packet(packet, kProtocol, kKey, opened));
  EXPECT_EQ(opened, body);

  EXPECT_FALSE(open_packet(packet, kProtocol + 1, kKey, opened));
  Key other = kKey;
  other[1] = 1;
  EXPECT_FALSE(open_packet(packet, kProtocol, other, opened));
  for (std::size_t i = 0; i < packet.size(); ++i) {  // any flipped bit: header, body or tag
    auto tampered = packet;
    tampered[i] ^= 0x10;
    EXPECT_FALSE(open_packet(tampered, kProtocol, kKey, opened)) << "byte " << i;
  }
}

TEST(EncryptedPacket, HeaderRefusesEmptyOversizedUnknownTypeAndShortPackets) {
  EXPECT_EQ(read_encrypted_header({}).error, DropReason::Empty);
  std::vector<std::uint8_t> big(kMaxDatagramBytes + 1, 4);
  EXPECT_EQ(read_encrypted_header(big).error, DropReason::Oversized);
  std::vector<std::uint8_t> unknown(64, 0);
  unknown[0] = 9;
  EXPECT_EQ(read_encrypted_header(unknown).error, DropReason::Malformed);
  const auto keep_alive =
      seal_packet(PacketType::KeepAlive, 1, kProtocol, kKey, write_keep_alive_body({3, 4}));
  std::vector<std::uint8_t> cut(keep_alive.begin(), keep_alive.end() - 1);
  EXPECT_EQ(read_encrypted_header(cut).error, DropReason::Truncated);
}

TEST(Bodies, RoundTripAndRefuseBadLengths) {
  ChallengeBody challenge;
  challenge.challenge_sequence = 99;
  challenge.challenge_token[5] = 8;
  auto parsed_challenge = read_challenge_body(write_challenge_body(challenge));
  ASSERT_TRUE(parsed_challenge.ok());
  EXPECT_EQ(parsed_challenge.value.challenge_sequence, 99u);
  EXPECT_EQ(parsed_challenge.value.challenge_token, challenge.challenge_token);
  EXPECT_FALSE(read_challenge_body(std::vector<std::uint8_t>(10)).ok());

  EXPECT_EQ(read_denied_body(write_denied_body(DisconnectReason::Denied)).value,
            DisconnectReason::Denied);
  EXPECT_FALSE(read_denied_body(std::vector<std::uint8_t>{200}).ok());

  auto disconnect =
      read_disconnect_body(write_disconnect_body({{5, 6}, DisconnectReason::Replaced}));
  ASSERT_TRUE(disconnect.ok());
  EXPECT_EQ(disconnect.value.reason, DisconnectReason::Replaced);
  EXPECT_EQ(disconnect.value.ack, (AckHeader{5, 6}));
  EXPECT_FALSE(read_keep_alive_body(std::vector<std::uint8_t>(5)).ok());
}

TEST(PayloadBody, CarriesReliableMessagesAndTheUnreliableRest) {
  PayloadBody body;
  body.ack = {1000, 0xF0F0F0F0};
  body.reliable = {{3, {1, 2}}, {4, std::vector<std::uint8_t>(kMaxReliableMessageBytes, 9)}};
  body.unreliable = {7, 7, 7};
  const std::vector<std::uint8_t> bytes = write_payload_body(body);
  // From a span (copying the rest) and from a body it takes (keeping the rest in its buffer).
  for (auto parsed : {read_payload_body(std::span<const std::uint8_t>(bytes)),
                      read_payload_body(std::vector<std::uint8_t>(bytes))}) {
    ASSERT_TRUE(parsed.ok());
    EXPECT_EQ(parsed.value.ack, body.ack);
    EXPECT_EQ(parsed.value.reliable, body.reliable);
    EXPECT_EQ(parsed.value.unreliable, body.unreliable);
  }
  body.reliable.clear();
  body.unreliable.clear();
  auto bare = read_payload_body(write_payload_body(body));
  ASSERT_TRUE(bare.ok());
  EXPECT_TRUE(bare.value.reliable.empty());
  EXPECT_TRUE(bare.value.unreliable.empty());
}

TEST(PayloadBody, RefusesLengthsPastTheEndEmptyAndOversizedMessages) {
  PayloadBody body;
  body.reliable = {{3, {1, 2, 3}}};
  auto bytes = write_payload_body(body);
  auto cut = bytes;
  cut.pop_back();
  EXPECT_EQ(read_payload_body(cut).error, DropReason::Truncated);
  auto empty_message = bytes;
  empty_message[kPayloadFixedBytes + 2] = 0;
  empty_message[kPayloadFixedBytes + 3] = 0;
  EXPECT_EQ(read_payload_body(empty_message).error, DropReason::Malformed);
  auto huge = bytes;
  huge[kPayloadFixedBytes + 2] = 0xFF;
  huge[kPayloadFixedBytes + 3] = 0x7F;
  EXPECT_EQ(read_payload_body(huge).error, DropReason::Malformed);
  EXPECT_EQ(read_payload_body(std::vector<std::uint8_t>(3)).error, DropReason::Truncated);
  // The same refusals from a body the reader takes.
  EXPECT_EQ(read_payload_body(std::vector<std::uint8_t>(cut)).error, DropReason::Truncated);
  EXPECT_EQ(read_payload_body(std::vector<std::uint8_t>(huge)).error, DropReason::Malformed);
}

TEST(PacketSizes, EveryHandshakeReplyIsSmallerThanTheRequest) {
  const std::size_t challenge = kEncryptedHeaderBytes + 8 + kChallengeTokenBytes + kMacBytes;
  const std::size_t denied = kEncryptedHeaderBytes + 1 + kMacBytes;
  EXPECT_LT(challenge, kConnectionRequestBytes);
  EXPECT_LT(denied, kConnectionRequestBytes);
  EXPECT_EQ(kEncryptedHeaderBytes + kMaxBodyBytes + kMacBytes, kMaxDatagramBytes);
}

template <class Enum>
std::set<std::string_view> names_of(std::size_t count) {
  std::set<std::string_view> names;
  for (std::size_t i = 0; i < count; ++i) names.insert(name(static_cast<Enum>(i)));
  return names;
}

TEST(Names, EveryReasonStateAndTypeHasItsOwnMetricLabel) {
  for (const auto& [names, count] :
       {std::pair{names_of<DropReason>(kDropReasonCount), kDropReasonCount},
        std::pair{names_of<DisconnectReason>(kDisconnectReasonCount), kDisconnectReasonCount},
        std::pair{names_of<ConnectionState>(kConnectionStateCount), kConnectionStateCount},
        std::pair{names_of<PacketType>(kPacketTypeCount), kPacketTypeCount}}) {
    EXPECT_EQ(names.size(), count);
    EXPECT_FALSE(names.contains("unknown")) << "an enum value without its name";
  }
}

}  // namespace
}  // namespace ricochet::proto::packet_test
