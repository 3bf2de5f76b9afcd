// The control channel under bad input over real sockets: oversize, empty and garbage frames,
// slowloris partial frames, idle and handshake deadlines, a plaintext or TLS 1.2 client, the
// connection caps, the message rate, and stopping. Each refusal is counted by its reason.
// Deadlines and the rate run on fake time the tests move (FakeTimeRig); none sleeps for one.

#include <gtest/gtest.h>

#include <atomic>
#include <future>
#include <thread>

#include "control_test_client.h"

namespace ricochet::server::test::control_limits_test {
namespace {

constexpr proto::TimeUs kMs = proto::kMicrosPerMilli;

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

/// ControlRig's server on fake time: its clock stands still until advance(), which then makes
/// every session look at its deadlines. (ControlRig alone runs on the steady clock.)
class FakeTimeRig {
 public:
  explicit FakeTimeRig(ControlLimits limits) : rig_(limits, [this] { return now_.load(); }) {}

  /// Moves the clock on by `us` and has every session compare its deadlines with it.
  void advance(proto::TimeUs us) {
    now_ += us;
    rig_.server().check_deadlines();
  }
  ControlServer& server() { return rig_.server(); }
  FakeDirectory& directory() { return rig_.directory(); }
  db::DbWorker& db() { return rig_.db(); }
  std::uint16_t port() const { return rig_.port(); }
  std::uint64_t refusals(ControlRefusal refusal) const { return rig_.refusals(refusal); }
  /// Waits (in real time, bounded) until the server holds `count` connections.
  bool wait_connections(std::size_t count) {
    for (int i = 0; i < 1000 && server().connections() != count; ++i) {
      std::this_thread::sleep_for(2ms);
    }
    return server().connections() == count;
  }

 private:
  std::atomic<proto::TimeUs> now_{1'000 * kMs};  ///< before rig_: its server reads it
  ControlRig rig_;
};

/// Sends a ping followed by `tail` in one write and waits for the pong: once it came, the
/// server has read `tail` too and started its frame deadline, at the rig's time now.
void ping_then(ControlTestClient& client, std::vector<std::uint8_t> tail) {
  std::vector<std::uint8_t> bytes;
  wire::ClientMessage ping = ControlTestClient::ping(1);
  ping.set_request_id(77);
  ASSERT_TRUE(proto::append_frame(ping, bytes));
  bytes.insert(bytes.end(), tail.begin(), tail.end());
  client.send_bytes(bytes);
  const auto reply = client.receive();
  ASSERT_TRUE(reply.has_value());
  EXPECT_EQ(reply->request_id(), 77u);
  EXPECT_TRUE(reply->has_pong());
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
  FakeTimeRig rig(limits);
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  ping_then(client, {0, 0});  // half a header, then nothing
  rig.advance(300 * kMs);
  expect_error_then_close(client, wire::FRAME_TIMEOUT);
  EXPECT_EQ(rig.refusals(ControlRefusal::FrameTimeout), 1u);
}

TEST(ControlLimits, AFrameFinishedJustInTimeIsAnswered) {
  ControlLimits limits;
  limits.frame_timeout_ms = 300;
  FakeTimeRig rig(limits);
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  std::vector<std::uint8_t> frame;
  wire::ClientMessage ping = ControlTestClient::ping(2);
  ping.set_request_id(78);
  ASSERT_TRUE(proto::append_frame(ping, frame));
  ping_then(client, {frame.begin(), frame.begin() + 3});
  rig.advance(300 * kMs - 1);
  client.send_bytes({frame.begin() + 3, frame.end()});
  const auto reply = client.receive();
  ASSERT_TRUE(reply.has_value());
  EXPECT_EQ(reply->request_id(), 78u);
  EXPECT_TRUE(reply->has_pong());
  EXPECT_EQ(rig.refusals(ControlRefusal::FrameTimeout), 0u);
}

TEST(ControlLimits, TricklingAFrameByteByByteDoesNotExtendItsDeadline) {
  ControlLimits limits;
  limits.frame_timeout_ms = 300;
  FakeTimeRig rig(limits);
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  std::vector<std::uint8_t> frame;
  ASSERT_TRUE(proto::append_frame(ControlTestClient::chat(std::string(40, 'x')), frame));
  ASSERT_GT(frame.size(), 31u);
  ping_then(client, {frame[0]});
  for (std::size_t i = 1; i <= 30; ++i) {  // a byte every 10 ms: 300 ms, the frame unfinished
    rig.advance(10 * kMs);
    client.send_bytes({frame[i]});
  }
  expect_error_then_close(client, wire::FRAME_TIMEOUT);
}

TEST(ControlLimits, IdleConnectionIsClosedAndPingsKeepItOpen) {
  ControlLimits limits;
  limits.idle_timeout_ms = 400;
  FakeTimeRig rig(limits);
  ControlTestClient pinging(rig.port());
  ASSERT_TRUE(pinging.connect());
  ControlTestClient idle(rig.port());
  ASSERT_TRUE(idle.connect());
  // A frame from each: both have had a whole frame at the same fake time.
  ASSERT_TRUE(pinging.request(ControlTestClient::ping(1)).has_pong());
  ASSERT_TRUE(idle.request(ControlTestClient::ping(1)).has_pong());
  rig.advance(300 * kMs);
  ASSERT_TRUE(pinging.request(ControlTestClient::ping(2)).has_pong());
  rig.advance(100 * kMs);  // 400 ms since idle's frame, 100 ms since pinging's
  expect_error_then_close(idle, wire::IDLE_TIMEOUT);
  EXPECT_EQ(rig.refusals(ControlRefusal::IdleTimeout), 1u);
  rig.advance(300 * kMs - 1);
  EXPECT_TRUE(pinging.request(ControlTestClient::ping(3)).has_pong());
  EXPECT_FALSE(pinging.closed());
}

// Issue 29: pings kept a connection that never logged in open for ever.
TEST(ControlLimits, AConnectionThatNeverLogsInIsClosedEvenIfItPings) {
  ControlLimits limits;
  limits.idle_timeout_ms = 400;
  limits.login_timeout_ms = 1'000;
  FakeTimeRig rig(limits);
  ControlTestClient lurker(rig.port());
  ASSERT_TRUE(lurker.connect());
  ControlTestClient player(rig.port());
  ASSERT_TRUE(player.connect());
  ASSERT_TRUE(rig.wait_connections(2));
  ASSERT_TRUE(player.request(ControlTestClient::register_account("ada", "lovelace1"))
                  .has_register_account());
  ASSERT_TRUE(player.request(ControlTestClient::login("ada", "lovelace1")).has_session());
  for (int i = 0; i < 3; ++i) {  // 900 ms of pings, every 300 ms: never idle
    ASSERT_TRUE(lurker.request(ControlTestClient::ping(i)).has_pong());
    ASSERT_TRUE(player.request(ControlTestClient::ping(i)).has_pong());
    rig.advance(300 * kMs);
  }
  ASSERT_TRUE(lurker.request(ControlTestClient::ping(3)).has_pong());
  ASSERT_TRUE(player.request(ControlTestClient::ping(3)).has_pong());
  rig.advance(100 * kMs);  // 1000 ms since the handshake
  expect_error_then_close(lurker, wire::LOGIN_TIMEOUT);
  EXPECT_EQ(rig.refusals(ControlRefusal::LoginTimeout), 1u);
  EXPECT_EQ(rig.refusals(ControlRefusal::IdleTimeout), 0u);
  // The logged-in player has no login deadline.
  EXPECT_TRUE(player.request(ControlTestClient::ping(4)).has_pong());
  EXPECT_FALSE(player.closed());
}

// Issue 29 (the sign-in storm): a registration that waited in the server's queues longer than
// the login deadline was answered, and its connection closed with LOGIN_TIMEOUT right after,
// so the client could never log in on it and registered again elsewhere.
TEST(ControlLimits, TheLoginDeadlineDoesNotCountTheTimeTheServerTookToAnswer) {
  ControlLimits limits;
  limits.login_timeout_ms = 1'000;
  FakeTimeRig rig(limits);
  ControlTestClient player(rig.port());
  ASSERT_TRUE(player.connect());
  ASSERT_TRUE(rig.wait_connections(1));
  // The database is busy: the registration waits behind another job.
  std::promise<void> release;
  std::atomic<bool> blocking{false};
  rig.db().submit(
      [&blocking, released = release.get_future().share()](db::DbServices&) {
        blocking = true;
        released.wait();
        return db::DbStatus();
      },
      [](std::function<void()> completion) { completion(); }, [](db::DbStatus) {});
  while (!blocking) std::this_thread::sleep_for(1ms);
  const auto frame_of = [](wire::ClientMessage message, std::uint32_t request_id) {
    message.set_request_id(request_id);
    std::vector<std::uint8_t> bytes;
    EXPECT_TRUE(proto::append_frame(message, bytes));
    return bytes;
  };
  player.send_bytes(frame_of(ControlTestClient::register_account("ada", "lovelace1"), 1));
  const auto registering = static_cast<std::size_t>(proto::ClientMessageKind::Register);
  for (int i = 0; i < 2000 && rig.server().stats().requests[registering] == 0; ++i) {
    std::this_thread::sleep_for(1ms);
  }
  ASSERT_EQ(rig.server().stats().requests[registering], 1u);
  rig.advance(3'000 * kMs);  // the server took three login deadlines to answer
  release.set_value();
  const auto registered = player.receive();
  ASSERT_TRUE(registered && registered->has_register_account())
      << (registered ? registered->DebugString() : "nothing");
  player.send_bytes(frame_of(ControlTestClient::login("ada", "lovelace1"), 2));
  const auto session = player.receive();
  ASSERT_TRUE(session && session->has_session()) << (session ? session->DebugString() : "nothing");
  EXPECT_EQ(rig.refusals(ControlRefusal::LoginTimeout), 0u);
}

TEST(ControlLimits, HandshakeMustFinishInTime) {
  ControlLimits limits;
  limits.handshake_timeout_ms = 200;
  FakeTimeRig rig(limits);
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect_tcp());     // and never says hello
  ASSERT_TRUE(rig.wait_connections(1));  // accepted: its deadline counts from now
  rig.advance(200 * kMs);
  const auto bytes = client.plain_bytes_until_closed(3s);
  ASSERT_TRUE(bytes.has_value()) << "the server did not close the silent connection";
  EXPECT_EQ(*bytes, 0u);
  EXPECT_EQ(rig.refusals(ControlRefusal::HandshakeTimeout), 1u);
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
  FakeTimeRig rig(limits);
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  const auto send_pings = [&client](std::uint32_t first, std::uint32_t last) {
    std::vector<std::uint8_t> burst;
    for (std::uint32_t i = first; i <= last; ++i) {
      wire::ClientMessage ping = ControlTestClient::ping(i);
      ping.set_request_id(i);
      EXPECT_TRUE(proto::append_frame(ping, burst));
    }
    client.send_bytes(burst);  // in one write
    int pongs = 0;
    for (std::uint32_t i = first; i <= last; ++i) {
      const auto reply = client.receive();
      if (!reply) break;
      EXPECT_EQ(reply->request_id(), i);  // in order
      if (reply->has_error()) {
        EXPECT_EQ(reply->error().code(), wire::RATE_LIMITED);
      }
      pongs += reply->has_pong();
    }
    return pongs;
  };
  EXPECT_EQ(send_pings(1, 6), 3);  // the burst
  EXPECT_EQ(rig.refusals(ControlRefusal::RateLimited), 3u);
  rig.advance(1'000 * kMs - 1);
  EXPECT_EQ(send_pings(7, 8), 0);  // the first token is not back yet
  rig.advance(1);
  EXPECT_EQ(send_pings(9, 10), 1);  // one token a second
  EXPECT_EQ(rig.refusals(ControlRefusal::RateLimited), 6u);
  EXPECT_FALSE(client.closed());
}

TEST(ControlLimits, ClientThatNeverReadsIsClosed) {
  ControlLimits limits;
  limits.messages_per_second = 10'000;
  limits.message_burst = 10'000;
  limits.max_outbox_bytes = 256 * 1024;
  FakeTimeRig rig(limits);
  for (int i = 0; i < 450; ++i) rig.directory().create({std::string(100, 'm'), 16, ""});
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  client.sign_in("ada");
  std::vector<std::uint8_t> requests;
  for (int i = 0; i < 400; ++i) {  // ~24 MB of replies, more than loopback buffers take
    ASSERT_TRUE(proto::append_frame(ControlTestClient::list_matches(), requests));
  }
  client.send_bytes(requests);  // and never read
  // The writes block and the replies pile up past the outbox cap; the clock stands still, so
  // the write deadline never comes.
  EXPECT_TRUE(rig.wait_connections(0));
  EXPECT_EQ(rig.refusals(ControlRefusal::OutboxFull), 1u);
  EXPECT_EQ(rig.refusals(ControlRefusal::WriteTimeout), 0u);
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
}  // namespace ricochet::server::test::control_limits_test
