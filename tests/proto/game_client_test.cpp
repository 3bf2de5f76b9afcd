/// The client end over time: resends, handshake timeout, silence timeout, queued reliables.
#include <gtest/gtest.h>

#include "transport_fixture.h"

namespace ricochet::proto::test::game_client_test {
namespace {

const Address kAlice = Address::ipv4(192, 0, 2, 10, 5000);
constexpr TimeUs kT0 = 10 * kMicrosPerSecond;
constexpr TimeUs kMs = kMicrosPerMilli;

TEST(GameClient, ResendsTheRequestAt10HzAndGivesUpAfterTheTimeout) {
  GameClient client(sim::connect_info(1, 1, kT0), kT0);
  int requests = 0;
  Transmit transmit;
  for (TimeUs t = kT0; t < kT0 + 5 * kMicrosPerSecond; t += kMs) {
    client.update(t);
    while (client.poll_transmit(transmit)) {
      EXPECT_EQ(transmit.bytes.size(), kConnectionRequestBytes);
      ++requests;
    }
  }
  EXPECT_EQ(requests, 50);
  EXPECT_EQ(client.state(), ConnectionState::SendingRequest);
  client.update(kT0 + 5 * kMicrosPerSecond);
  EXPECT_EQ(client.state(), ConnectionState::Disconnected);
  EXPECT_EQ(client.disconnect_reason(), DisconnectReason::HandshakeTimedOut);
  ClientEvent event;
  ASSERT_TRUE(client.poll_event(event));
  EXPECT_EQ(std::get<ClientDisconnected>(event).reason, DisconnectReason::HandshakeTimedOut);
  client.update(kT0 + 6 * kMicrosPerSecond);
  EXPECT_FALSE(client.poll_transmit(transmit)) << "a disconnected client is silent";
}

TEST_F(TransportTest, AConnectedClientKeepsAliveAt10HzAndTimesOutWhenTheServerGoesSilent) {
  auto alice = connected_client(1, kAlice, kT0);
  client_events(*alice);
  int keep_alives = 0;
  for (TimeUs t = kT0 + kMs; t < kT0 + 5 * kMicrosPerSecond; t += kMs) {
    alice->update(t);
    keep_alives += static_cast<int>(client_out(*alice).size());
  }
  EXPECT_EQ(keep_alives, 49);
  EXPECT_EQ(alice->state(), ConnectionState::Connected);
  alice->update(kT0 + 5 * kMicrosPerSecond);
  EXPECT_EQ(alice->disconnect_reason(), DisconnectReason::TimedOut);
}

TEST_F(TransportTest, ReliableMessagesQueuedBeforeConnectingAreSentOnceConnected) {
  GameClient client(sim::connect_info(3, 1, kT0), kT0);
  EXPECT_FALSE(client.send_unreliable(std::vector<std::uint8_t>{1}, kT0)) << "not connected";
  ASSERT_TRUE(client.send_reliable(std::vector<std::uint8_t>{'h', 'i'}, kT0));
  exchange(client, kAlice, kT0);
  ASSERT_EQ(client.state(), ConnectionState::Connected);
  client.update(kT0 + kMs);
  exchange(client, kAlice, kT0 + kMs);
  auto events = server_events();
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(std::get<ServerReliable>(events[1]).bytes, (std::vector<std::uint8_t>{'h', 'i'}));
}

// As the server end's: a kept Transmit gets back, two payloads later, the buffer it handed in,
// and every packet still reaches the server with its own bytes.
TEST_F(TransportTest, TheClientsPolledTransmitsHandTheirBuffersBack) {
  auto alice = connected_client(1, kAlice, kT0);
  server_events();
  server_out();
  Transmit kept;
  std::vector<const std::uint8_t*> buffers;
  for (std::uint8_t n = 1; n <= 5; ++n) {
    ASSERT_TRUE(alice->send_unreliable(std::vector<std::uint8_t>(40, n), kT0));
    ASSERT_TRUE(alice->poll_transmit(kept));
    EXPECT_FALSE(alice->poll_transmit(kept));
    buffers.push_back(kept.bytes.data());
    server->receive(kAlice, kept.bytes, kT0);
    auto events = server_events();
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(std::get<ServerUnreliable>(events[0]).bytes, std::vector<std::uint8_t>(40, n));
  }
  EXPECT_EQ(buffers[2], buffers[0]);
  EXPECT_EQ(buffers[3], buffers[1]);
  EXPECT_NE(buffers[0], buffers[1]);
}

TEST_F(TransportTest, DisconnectBeforeConnectingSendsNothing) {
  GameClient client(sim::connect_info(3, 1, kT0), kT0);
  client_out(client);
  client.disconnect(kT0);
  EXPECT_TRUE(client_out(client).empty());
  EXPECT_EQ(client.disconnect_reason(), DisconnectReason::Requested);
  EXPECT_FALSE(client.send_reliable(std::vector<std::uint8_t>{1}, kT0));
}

}  // namespace
}  // namespace ricochet::proto::test::game_client_test
