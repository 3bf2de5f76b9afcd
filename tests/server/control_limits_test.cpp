// The control channel under bad input over real sockets: oversize, empty and garbage frames,
// slowloris partial frames, idle and handshake deadlines, a plaintext or TLS 1.2 client, the
// connection caps, the message rate, and stopping. Each refusal is counted by its reason.

#include <gtest/gtest.h>

#include "control_test_client.h"

namespace ricochet::server::test {
namespace {

std::vector<std::uint8_t> header(std::uint32_t length) {
  return {static_cast<std::uint8_t>(length >> 24), static_cast<std::uint8_t>(length >> 16),
          static_cast<std::uint8_t>(length >> 8), static_cast<std::uint8_t>(length)};
}

/// Expects an Error with `code` and request_id 0, then the server closing the connection.
void expect_error_then_close(ControlTestClient& client, wire::ErrorCode code) {
  std::vector<wire::ServerMessage> before;
  EXPECT_TRUE(client.wait_closed(5s, &before));
  ASSERT_EQ(before.size(), 1u);
  EXPECT_EQ(before[0].request_id(), 0u);
  EXPECT_EQ(before[0].error().code(), code) << before[0].DebugString();
  EXPECT_FALSE(before[0].error().message().empty());
}

TEST(ControlLimits, OversizeFrameIsRefusedAtItsHeaderThenClosed) {
  ControlRig rig;
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  client.send_bytes(header(proto::kMaxFramePayloadBytes + 1));
  expect_error_then_close(client, wire::FRAME_TOO_LARGE);
  EXPECT_EQ(rig.refusals(ControlRefusal::FrameOversize), 1u);
}

TEST(ControlLimits, GarbagePayloadIsMalformedThenClosed) {
  ControlRig rig;
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  std::vector<std::uint8_t> frame = header(5);
  for (std::uint8_t byte : {0xff, 0xff, 0xff, 0xff, 0x0f}) frame.push_back(byte);
  client.send_bytes(frame);
  expect_error_then_close(client, wire::MALFORMED);
  EXPECT_EQ(rig.refusals(ControlRefusal::FrameMalformed), 1u);
}

TEST(ControlLimits, EmptyFrameIsMalformedThenClosed) {
  ControlRig rig;
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  client.send_bytes(header(0));
  expect_error_then_close(client, wire::MALFORMED);
  EXPECT_EQ(rig.refusals(ControlRefusal::FrameEmpty), 1u);
}

TEST(ControlLimits, SlowlorisPartialFrameTimesOut) {
  ControlLimits limits;
  limits.frame_timeout_ms = 300;
  ControlRig rig(limits);
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  client.send_bytes({0, 0});  // half a header, then nothing
  const auto started = std::chrono::steady_clock::now();
  expect_error_then_close(client, wire::FRAME_TIMEOUT);
  EXPECT_LT(std::chrono::steady_clock::now() - started, 2s);
  EXPECT_EQ(rig.refusals(ControlRefusal::FrameTimeout), 1u);
}

TEST(ControlLimits, TricklingAFrameByteByByteDoesNotExtendItsDeadline) {
  ControlLimits limits;
  limits.frame_timeout_ms = 300;
  ControlRig rig(limits);
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  std::vector<std::uint8_t> frame;
  ASSERT_TRUE(proto::append_frame(ControlTestClient::chat(std::string(40, 'x')), frame));
  for (std::uint8_t byte : frame) {
    client.send_bytes({byte});
    if (rig.refusals(ControlRefusal::FrameTimeout) > 0) break;
    std::this_thread::sleep_for(30ms);  // 46 bytes * 30 ms > 300 ms
  }
  expect_error_then_close(client, wire::FRAME_TIMEOUT);
}

TEST(ControlLimits, IdleConnectionIsClosedAndPingsKeepItOpen) {
  ControlLimits limits;
  limits.idle_timeout_ms = 400;
  ControlRig rig(limits);
  ControlTestClient pinging(rig.port());
  ASSERT_TRUE(pinging.connect());
  ControlTestClient idle(rig.port());
  ASSERT_TRUE(idle.connect());
  for (int i = 0; i < 8; ++i) {  // 800 ms of pings every 100 ms
    ASSERT_TRUE(pinging.request(ControlTestClient::ping(i)).has_pong());
    std::this_thread::sleep_for(100ms);
  }
  expect_error_then_close(idle, wire::IDLE_TIMEOUT);
  EXPECT_EQ(rig.refusals(ControlRefusal::IdleTimeout), 1u);
  EXPECT_TRUE(pinging.request(ControlTestClient::ping(99)).has_pong());
}

TEST(ControlLimits, HandshakeMustFinishInTime) {
  ControlLimits limits;
  limits.handshake_timeout_ms = 200;
  ControlRig rig(limits);
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect_tcp());  // and never says hello
  const auto bytes = client.plain_bytes_until_closed(3s);
  ASSERT_TRUE(bytes.has_value()) << "the server did not close the silent connection";
  EXPECT_EQ(*bytes, 0u);
  EXPECT_TRUE(rig.wait_refusals(ControlRefusal::HandshakeTimeout, 1));
}

TEST(ControlLimits, PlaintextClientGetsOnlyAClosedConnection) {
  ControlRig rig;
  for (const std::string& plaintext :
       {std::string("GET / HTTP/1.1\r\nHost: localhost\r\n\r\n"),
        std::string("\x00\x00\x00\x04\x52\x02\x08\x01", 8)}) {  // a ClientMessage frame, no TLS
    ControlTestClient client(rig.port());
    ASSERT_TRUE(client.connect_tcp());
    client.send_plain(plaintext);
    const auto bytes = client.plain_bytes_until_closed(3s);
    ASSERT_TRUE(bytes.has_value()) << "the server did not close the plaintext connection";
    EXPECT_EQ(*bytes, 0u) << "the server answered a plaintext client";
  }
  EXPECT_TRUE(rig.wait_refusals(ControlRefusal::TlsHandshakeFailed, 2));
}

TEST(ControlLimits, Tls12ClientIsRefused) {
  ControlRig rig;
  ControlTestClient client(rig.port(), TLS1_2_VERSION);
  EXPECT_FALSE(client.connect());
  EXPECT_TRUE(rig.wait_refusals(ControlRefusal::TlsHandshakeFailed, 1));
}

TEST(ControlLimits, ConnectionCapRefusesTheOneTooMany) {
  ControlLimits limits;
  limits.max_connections = 2;
  limits.max_connections_per_address = 2;
  ControlRig rig(limits);
  auto first = std::make_unique<ControlTestClient>(rig.port());
  ControlTestClient second(rig.port());
  ASSERT_TRUE(first->connect());
  ASSERT_TRUE(second.connect());
  ControlTestClient third(rig.port());
  EXPECT_FALSE(third.connect());
  EXPECT_TRUE(rig.wait_refusals(ControlRefusal::ConnectionCap, 1));
  // A place frees when a client leaves.
  first.reset();
  for (int i = 0; i < 200 && rig.server().connections() > 1; ++i) std::this_thread::sleep_for(5ms);
  ControlTestClient fourth(rig.port());
  EXPECT_TRUE(fourth.connect());
  EXPECT_TRUE(second.request(ControlTestClient::ping(1)).has_pong());
}

TEST(ControlLimits, PerAddressCapRefusesTheOneTooMany) {
  ControlLimits limits;
  limits.max_connections_per_address = 1;
  ControlRig rig(limits);
  ControlTestClient first(rig.port());
  ASSERT_TRUE(first.connect());
  ControlTestClient second(rig.port());
  EXPECT_FALSE(second.connect());
  EXPECT_TRUE(rig.wait_refusals(ControlRefusal::AddressCap, 1));
  EXPECT_EQ(rig.refusals(ControlRefusal::ConnectionCap), 0u);
}

TEST(ControlLimits, OverTheMessageRateIsDroppedWithAnError) {
  ControlLimits limits;
  limits.messages_per_second = 1;
  limits.message_burst = 3;
  ControlRig rig(limits);
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  std::vector<std::uint8_t> burst;
  for (int i = 1; i <= 6; ++i) {
    wire::ClientMessage ping = ControlTestClient::ping(static_cast<std::uint64_t>(i));
    ping.set_request_id(static_cast<std::uint32_t>(i));
    ASSERT_TRUE(proto::append_frame(ping, burst));
  }
  client.send_bytes(burst);  // six requests in one write
  int pongs = 0;
  int limited = 0;
  for (int i = 1; i <= 6; ++i) {
    const auto reply = client.receive();
    ASSERT_TRUE(reply);
    EXPECT_EQ(reply->request_id(), static_cast<std::uint32_t>(i));  // in order
    pongs += reply->has_pong();
    limited += reply->has_error() && reply->error().code() == wire::RATE_LIMITED;
  }
  EXPECT_EQ(pongs, 3);
  EXPECT_EQ(limited, 3);
  EXPECT_EQ(rig.refusals(ControlRefusal::RateLimited), 3u);
  EXPECT_FALSE(client.closed());
}

TEST(ControlLimits, ClientThatNeverReadsIsClosed) {
  ControlLimits limits;
  limits.messages_per_second = 10'000;
  limits.message_burst = 10'000;
  limits.write_timeout_ms = 300;
  limits.max_outbox_bytes = 256 * 1024;
  ControlRig rig(limits);
  for (int i = 0; i < 450; ++i) rig.directory().create({std::string(100, 'm'), 16, ""});
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  client.sign_in("ada");
  std::vector<std::uint8_t> requests;
  for (int i = 0; i < 400; ++i) {  // ~24 MB of replies, more than loopback buffers take
    ASSERT_TRUE(proto::append_frame(ControlTestClient::list_matches(), requests));
  }
  client.send_bytes(requests);  // and never read
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  while (rig.refusals(ControlRefusal::OutboxFull) + rig.refusals(ControlRefusal::WriteTimeout) ==
             0 &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(5ms);
  }
  EXPECT_EQ(rig.refusals(ControlRefusal::OutboxFull) + rig.refusals(ControlRefusal::WriteTimeout),
            1u);
  for (int i = 0; i < 200 && rig.server().connections() > 0; ++i) std::this_thread::sleep_for(5ms);
  EXPECT_EQ(rig.server().connections(), 0u);
}

TEST(ControlLimits, StopTellsEveryClientAndCloses) {
  ControlRig rig;
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  client.sign_in("ada");
  EXPECT_EQ(
      rig.server().stats().by_state[static_cast<std::size_t>(proto::ControlState::Authenticated)],
      1u);
  rig.server().stop();
  expect_error_then_close(client, wire::SHUTTING_DOWN);
  ControlTestClient late(rig.port());
  EXPECT_FALSE(late.connect(1s));
}

TEST(ControlLimits, CountersFollowTheConnections) {
  ControlRig rig;
  {
    ControlTestClient client(rig.port());
    ASSERT_TRUE(client.connect());
    EXPECT_TRUE(client.request(ControlTestClient::ping(1)).has_pong());
    const ControlStats stats = rig.server().stats();
    EXPECT_EQ(stats.accepted, 1u);
    EXPECT_EQ(stats.handshakes, 1u);
    EXPECT_EQ(stats.frames_in, 1u);
    EXPECT_EQ(stats.frames_out, 1u);
    EXPECT_GT(stats.bytes_in, 0u);
    EXPECT_EQ(stats.requests[static_cast<std::size_t>(proto::ClientMessageKind::Ping)], 1u);
  }
  for (int i = 0; i < 200 && rig.server().connections() > 0; ++i) std::this_thread::sleep_for(5ms);
  const ControlStats stats = rig.server().stats();
  EXPECT_EQ(stats.closed, 1u);
  for (std::uint64_t in_state : stats.by_state) EXPECT_EQ(in_state, 0u);
  EXPECT_EQ(stats.handshaking, 0u);
}

}  // namespace
}  // namespace ricochet::server::test
