// The control channel's framing: frames split anywhere reassemble in order; oversize and empty
// frames are refused at their header; payloads that are not messages, or have no body, are
// refused with their reason; the state table admits exactly what PROTOCOL.md says.

#include "ricochet/proto/frame.h"

#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "ricochet/proto/control_states.h"

namespace ricochet::proto::frame_test {
namespace {

wire::ClientMessage login(std::uint32_t request_id, const std::string& username) {
  wire::ClientMessage message;
  message.set_request_id(request_id);
  message.mutable_login()->set_username(username);
  message.mutable_login()->set_password("correct horse");
  return message;
}

std::vector<std::uint8_t> header(std::uint32_t length) {
  return {static_cast<std::uint8_t>(length >> 24), static_cast<std::uint8_t>(length >> 16),
          static_cast<std::uint8_t>(length >> 8), static_cast<std::uint8_t>(length)};
}

TEST(Frame, HeaderIsTheBigEndianPayloadLength) {
  std::vector<std::uint8_t> bytes;
  const wire::ClientMessage message = login(7, "ada");
  ASSERT_TRUE(append_frame(message, bytes));
  const std::size_t size = message.ByteSizeLong();
  ASSERT_EQ(bytes.size(), kFrameHeaderBytes + size);
  EXPECT_EQ(std::vector<std::uint8_t>(bytes.begin(), bytes.begin() + 4),
            header(static_cast<std::uint32_t>(size)));
}

TEST(Frame, FramesSplitAtEveryByteReassembleInOrder) {
  std::vector<std::uint8_t> stream;
  for (std::uint32_t i = 1; i <= 5; ++i)
    ASSERT_TRUE(append_frame(login(i, "user" + std::to_string(i)), stream));

  FrameReader reader;
  std::vector<std::uint8_t> payload;
  std::vector<std::uint32_t> ids;
  for (std::uint8_t byte : stream) {
    reader.feed(std::span<const std::uint8_t>(&byte, 1));
    while (reader.next(payload) == FrameReader::Status::Frame) {
      wire::ClientMessage message;
      ASSERT_EQ(parse_client_message(payload, message), std::nullopt);
      EXPECT_EQ(message.login().username(), "user" + std::to_string(message.request_id()));
      ids.push_back(message.request_id());
    }
  }
  EXPECT_EQ(ids, (std::vector<std::uint32_t>{1, 2, 3, 4, 5}));
  EXPECT_FALSE(reader.inside_frame());
}

TEST(Frame, RandomSplitsOfManyFramesReassemble) {
  std::mt19937 random(11);
  std::vector<std::uint8_t> stream;
  std::vector<std::string> sent;
  for (int i = 0; i < 200; ++i) {
    wire::ClientMessage message;
    message.set_request_id(static_cast<std::uint32_t>(i + 1));
    std::string text(random() % 3000, static_cast<char>('a' + i % 26));
    message.mutable_chat()->set_text(text);
    sent.push_back(text);
    ASSERT_TRUE(append_frame(message, stream));
  }
  FrameReader reader;
  std::vector<std::uint8_t> payload;
  std::vector<std::string> received;
  for (std::size_t at = 0; at < stream.size();) {
    const std::size_t chunk = std::min<std::size_t>(stream.size() - at, 1 + random() % 9000);
    reader.feed(std::span(stream).subspan(at, chunk));
    at += chunk;
    while (reader.next(payload) == FrameReader::Status::Frame) {
      wire::ClientMessage message;
      ASSERT_EQ(parse_client_message(payload, message), std::nullopt);
      received.push_back(message.chat().text());
    }
  }
  EXPECT_EQ(received, sent);
}

TEST(Frame, PartialFrameIsInsideFrameUntilComplete) {
  std::vector<std::uint8_t> stream;
  ASSERT_TRUE(append_frame(login(1, "ada"), stream));
  FrameReader reader;
  std::vector<std::uint8_t> payload;
  reader.feed(std::span(stream).first(2));
  EXPECT_TRUE(reader.inside_frame());
  EXPECT_EQ(reader.next(payload), FrameReader::Status::NeedMore);
  reader.feed(std::span(stream).subspan(2, stream.size() - 3));
  EXPECT_EQ(reader.next(payload), FrameReader::Status::NeedMore);
  reader.feed(std::span(stream).last(1));
  EXPECT_EQ(reader.next(payload), FrameReader::Status::Frame);
  EXPECT_FALSE(reader.inside_frame());
}

TEST(Frame, LargestFrameIsAcceptedOneMoreIsRefusedAtItsHeader) {
  FrameReader reader;
  std::vector<std::uint8_t> payload;
  std::vector<std::uint8_t> largest = header(kMaxFramePayloadBytes);
  largest.resize(kFrameHeaderBytes + kMaxFramePayloadBytes, 0);
  reader.feed(largest);
  ASSERT_EQ(reader.next(payload), FrameReader::Status::Frame);
  EXPECT_EQ(payload.size(), kMaxFramePayloadBytes);

  reader.feed(header(kMaxFramePayloadBytes + 1));  // no payload bytes needed to refuse it
  EXPECT_EQ(reader.next(payload), FrameReader::Status::Refused);
  EXPECT_EQ(reader.refusal(), FrameRefusal::Oversize);
  EXPECT_EQ(reader.refused_length(), kMaxFramePayloadBytes + 1);
  EXPECT_EQ(reader.buffered(), 0u);
  reader.feed(header(3));  // sticky: the stream stays refused
  EXPECT_EQ(reader.next(payload), FrameReader::Status::Refused);
}

TEST(Frame, HugeDeclaredLengthIsRefused) {
  FrameReader reader;
  std::vector<std::uint8_t> payload;
  reader.feed(std::vector<std::uint8_t>{0xff, 0xff, 0xff, 0xff});
  EXPECT_EQ(reader.next(payload), FrameReader::Status::Refused);
  EXPECT_EQ(reader.refusal(), FrameRefusal::Oversize);
}

TEST(Frame, EmptyFrameIsRefused) {
  FrameReader reader;
  std::vector<std::uint8_t> payload;
  reader.feed(header(0));
  EXPECT_EQ(reader.next(payload), FrameReader::Status::Refused);
  EXPECT_EQ(reader.refusal(), FrameRefusal::Empty);
}

TEST(Frame, GarbagePayloadIsMalformed) {
  wire::ClientMessage message;
  const std::vector<std::uint8_t> garbage{0xff, 0xff, 0xff, 0xff, 0x0f};  // field 0, bad varint
  EXPECT_EQ(parse_client_message(garbage, message), FrameRefusal::Malformed);
  const std::vector<std::uint8_t> truncated{0x1a, 0x10, 0x0a};  // login declares 16 bytes, has 1
  EXPECT_EQ(parse_client_message(truncated, message), FrameRefusal::Malformed);
}

TEST(Frame, InvalidUtf8StringIsMalformed) {
  // request_id 1, login { username: "\xff\xfe" }
  const std::vector<std::uint8_t> payload{0x08, 0x01, 0x1a, 0x04, 0x0a, 0x02, 0xff, 0xfe};
  wire::ClientMessage message;
  EXPECT_EQ(parse_client_message(payload, message), FrameRefusal::Malformed);
}

TEST(Frame, MessageWithoutBodyIsRefused) {
  wire::ClientMessage message;
  message.set_request_id(3);
  std::vector<std::uint8_t> bytes;
  ASSERT_TRUE(append_frame(message, bytes));
  wire::ClientMessage parsed;
  EXPECT_EQ(parse_client_message(std::span(bytes).subspan(kFrameHeaderBytes), parsed),
            FrameRefusal::MissingBody);
}

TEST(Frame, ServerMessageRoundTrips) {
  wire::ServerMessage message;
  message.set_request_id(9);
  message.mutable_error()->set_code(wire::WRONG_STATE);
  message.mutable_error()->set_message("chat needs in_match, the connection is unauthenticated");
  std::vector<std::uint8_t> bytes;
  ASSERT_TRUE(append_frame(message, bytes));
  FrameReader reader;
  reader.feed(bytes);
  std::vector<std::uint8_t> payload;
  ASSERT_EQ(reader.next(payload), FrameReader::Status::Frame);
  wire::ServerMessage parsed;
  ASSERT_EQ(parse_server_message(payload, parsed), std::nullopt);
  EXPECT_EQ(parsed.request_id(), 9u);
  EXPECT_EQ(parsed.error().code(), wire::WRONG_STATE);
}

TEST(Frame, MessageOverTheLimitIsNotFramed) {
  wire::ClientMessage message;
  message.mutable_chat()->set_text(std::string(kMaxFramePayloadBytes, 'x'));
  std::vector<std::uint8_t> bytes{1, 2};
  EXPECT_FALSE(append_frame(message, bytes));
  EXPECT_EQ(bytes, (std::vector<std::uint8_t>{1, 2}));
}

TEST(ControlStates, TableAdmitsWhatEachStateAllows) {
  using K = ClientMessageKind;
  using S = ControlState;
  EXPECT_TRUE(admits(S::Unauthenticated, K::Login));
  EXPECT_TRUE(admits(S::Unauthenticated, K::Register));
  EXPECT_TRUE(admits(S::Unauthenticated, K::Resume));
  EXPECT_FALSE(admits(S::Unauthenticated, K::JoinMatch));
  EXPECT_FALSE(admits(S::Unauthenticated, K::Chat));
  EXPECT_FALSE(admits(S::Authenticated, K::Login));
  EXPECT_TRUE(admits(S::Authenticated, K::JoinMatch));
  EXPECT_FALSE(admits(S::Authenticated, K::Chat));
  EXPECT_FALSE(admits(S::Authenticated, K::LeaveMatch));
  EXPECT_TRUE(admits(S::InMatch, K::Chat));
  EXPECT_TRUE(admits(S::InMatch, K::LeaveMatch));
  EXPECT_FALSE(admits(S::Unauthenticated, K::Logout));
  EXPECT_TRUE(admits(S::Authenticated, K::Logout));
  EXPECT_TRUE(admits(S::InMatch, K::Logout));
  EXPECT_FALSE(admits(S::Unauthenticated, K::FindMatch));
  EXPECT_TRUE(admits(S::Authenticated, K::FindMatch));
  EXPECT_TRUE(admits(S::InMatch, K::FindMatch));
  for (std::size_t k = 0; k < kClientMessageKindCount; ++k) {
    EXPECT_FALSE(admits(S::Closed, static_cast<K>(k))) << name(static_cast<K>(k));
  }
  for (S state : {S::Unauthenticated, S::Authenticated, S::InMatch}) {
    EXPECT_TRUE(admits(state, K::Ping)) << name(state);
  }
}

TEST(ControlStates, TransitionsReportOnceAndClosedIsFinal) {
  std::vector<std::string> log;
  ControlStateMachine machine([&](ControlState from, ControlState to, std::string_view reason) {
    log.push_back(std::string(name(from)) + ">" + name(to) + ":" + std::string(reason));
  });
  EXPECT_TRUE(machine.transition(ControlState::Authenticated, "login"));
  EXPECT_FALSE(machine.transition(ControlState::Authenticated, "login again"));
  EXPECT_TRUE(machine.transition(ControlState::Closed, "idle"));
  EXPECT_FALSE(machine.transition(ControlState::Unauthenticated, "after close"));
  EXPECT_EQ(log, (std::vector<std::string>{"unauthenticated>authenticated:login",
                                           "authenticated>closed:idle"}));
  EXPECT_FALSE(machine.admits(ClientMessageKind::Ping));
}

TEST(ControlStates, KindFollowsTheBody) {
  wire::ClientMessage message;
  message.mutable_join_match()->set_match_id(4);
  EXPECT_EQ(kind_of(message), ClientMessageKind::JoinMatch);
  message.mutable_chat()->set_text("hi");
  EXPECT_EQ(kind_of(message), ClientMessageKind::Chat);
}

}  // namespace
}  // namespace ricochet::proto::frame_test
