/// The server end over time: keep-alives, timeouts, reconnects, the one exit, reliable caps.
#include <gtest/gtest.h>

#include "transport_fixture.h"

namespace ricochet::proto::test::game_server_test {
namespace {

const Address kAlice = Address::ipv4(192, 0, 2, 10, 5000);
const Address kAliceOnMobile = Address::ipv4(100, 64, 0, 7, 41000);
constexpr TimeUs kT0 = 50 * kMicrosPerSecond;
constexpr TimeUs kMs = kMicrosPerMilli;

ClientId connected_id(const std::vector<ServerEvent>& events) {
  for (const ServerEvent& event : events) {
    if (const auto* connected = std::get_if<ServerConnected>(&event)) return connected->client;
  }
  return 0;
}

TEST_F(TransportTest, IdleServerSendsKeepAlivesAt10Hz) {
  auto alice = connected_client(1, kAlice, kT0);
  server_out();
  int keep_alives = 0;
  for (TimeUs t = kT0 + kMs; t <= kT0 + kMicrosPerSecond; t += kMs) {
    server->update(t);
    for (const Transmit& transmit : server_out()) {
      EXPECT_EQ(transmit.to, kAlice);
      EXPECT_EQ(static_cast<PacketType>(transmit.bytes[0]), PacketType::KeepAlive);
      ++keep_alives;
    }
  }
  EXPECT_EQ(keep_alives, 10);
}

TEST_F(TransportTest, AClientSilentForItsTimeoutIsDroppedOnce) {
  auto alice = connected_client(1, kAlice, kT0);
  const ClientId id = connected_id(server_events());
  server->update(kT0 + 5 * kMicrosPerSecond - 1);
  EXPECT_TRUE(server->connected(id));
  server->update(kT0 + 5 * kMicrosPerSecond);
  EXPECT_FALSE(server->connected(id));
  auto events = server_events();
  ASSERT_EQ(events.size(), 1u);
  const auto& gone = std::get<ServerDisconnected>(events[0]);
  EXPECT_EQ(gone.client, id);
  EXPECT_EQ(gone.account_id, 1u);
  EXPECT_EQ(gone.reason, DisconnectReason::TimedOut);
  EXPECT_EQ(server->counters().disconnects[static_cast<std::size_t>(DisconnectReason::TimedOut)],
            1u);
  EXPECT_EQ(server_transitions.back().reason, "timed_out");
  server->update(kT0 + 6 * kMicrosPerSecond);
  EXPECT_TRUE(server_events().empty());
}

TEST_F(TransportTest, KeepAlivesFromTheClientKeepItConnected) {
  auto alice = connected_client(1, kAlice, kT0);
  const ClientId id = connected_id(server_events());
  for (TimeUs t = kT0; t <= kT0 + 20 * kMicrosPerSecond; t += 10 * kMs) {
    alice->update(t);
    server->update(t);
    exchange(*alice, kAlice, t);
  }
  EXPECT_TRUE(server->connected(id));
  EXPECT_EQ(alice->state(), ConnectionState::Connected);
}

TEST_F(TransportTest, ReconnectFromANewAddressReplacesTheOldConnection) {
  auto old_client = connected_client(42, kAlice, kT0);
  const ClientId old_id = connected_id(server_events());
  server_out();
  auto new_client = std::make_unique<GameClient>(sim::connect_info(42, 1, kT0 + kMs), kT0 + kMs);
  // Deliver by hand so that the disconnect for the old address can be seen.
  for (int round = 0; round < 3; ++round) {
    for (const Transmit& t : client_out(*new_client))
      server->receive(kAliceOnMobile, t.bytes, kT0 + kMs);
    for (const Transmit& t : server_out()) {
      if (t.to == kAliceOnMobile) new_client->receive(kServerAddress, t.bytes, kT0 + kMs);
      if (t.to == kAlice) old_client->receive(kServerAddress, t.bytes, kT0 + kMs);
    }
  }
  EXPECT_EQ(new_client->state(), ConnectionState::Connected);
  EXPECT_EQ(old_client->state(), ConnectionState::Disconnected);
  EXPECT_EQ(old_client->disconnect_reason(), DisconnectReason::Replaced);
  auto events = server_events();
  ASSERT_EQ(events.size(), 2u);
  const auto& replaced = std::get<ServerDisconnected>(events[0]);
  EXPECT_EQ(replaced.client, old_id);
  EXPECT_EQ(replaced.reason, DisconnectReason::Replaced);
  const auto& reconnected = std::get<ServerConnected>(events[1]);
  EXPECT_NE(reconnected.client, old_id) << "ids are never reused";
  EXPECT_EQ(reconnected.account_id, 42u);
  EXPECT_EQ(reconnected.address, kAliceOnMobile);
  EXPECT_EQ(server->client_count(), 1u);
  EXPECT_FALSE(server->send_unreliable(old_id, std::vector<std::uint8_t>{1}, kT0 + kMs));
}

TEST_F(TransportTest, AppDisconnectTellsTheClientAndReportsOnce) {
  auto alice = connected_client(7, kAlice, kT0);
  const ClientId id = connected_id(server_events());
  server_out();
  server->disconnect(id, DisconnectReason::Kicked, kT0 + kMs);
  auto packets = server_out();
  EXPECT_EQ(packets.size(), 3u) << "three copies against loss";
  for (const Transmit& t : packets) alice->receive(kServerAddress, t.bytes, kT0 + kMs);
  EXPECT_EQ(alice->disconnect_reason(), DisconnectReason::Kicked);
  EXPECT_EQ(alice->counters().dropped(DropReason::WrongState), 2u) << "the copies after the first";
  auto events = server_events();
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(std::get<ServerDisconnected>(events[0]).reason, DisconnectReason::Kicked);
  server->disconnect(id, DisconnectReason::Kicked, kT0 + 2 * kMs);
  EXPECT_TRUE(server_events().empty());
}

TEST_F(TransportTest, ClientDisconnectEndsTheConnectionOnTheServer) {
  auto alice = connected_client(7, kAlice, kT0);
  connected_id(server_events());
  alice->disconnect(kT0 + kMs);
  exchange(*alice, kAlice, kT0 + kMs);
  auto events = server_events();
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(std::get<ServerDisconnected>(events[0]).reason, DisconnectReason::PeerRequested);
  EXPECT_EQ(server->client_count(), 0u);
  EXPECT_EQ(drops(DropReason::UnknownAddress), 2u) << "the two extra copies";
}

TEST_F(TransportTest, DisconnectAllEndsEveryClient) {
  auto a = connected_client(1, Address::ipv4(1, 2, 3, 4, 1), kT0);
  auto b = connected_client(2, Address::ipv4(1, 2, 3, 5, 1), kT0);
  server_events();
  server->disconnect_all(DisconnectReason::ServerShutdown, kT0);
  EXPECT_EQ(server->client_count(), 0u);
  EXPECT_EQ(server_events().size(), 2u);
  EXPECT_EQ(server_out().size(), 6u);
}

TEST_F(TransportTest, ReliableMessagesReachTheClientInOrderAndTheCapDisconnects) {
  GameServerConfig config = sim::test_server_config();
  config.max_reliable_pending = 4;
  config.max_reliable_queued = 4;
  start(config);
  auto alice = connected_client(7, kAlice, kT0);
  const ClientId id = connected_id(server_events());
  for (std::uint8_t i = 0; i < 4; ++i) {
    ASSERT_TRUE(server->send_reliable(id, std::vector<std::uint8_t>{i}, kT0));
  }
  EXPECT_FALSE(server->send_reliable(id, {}, kT0)) << "empty";
  EXPECT_FALSE(
      server->send_reliable(id, std::vector<std::uint8_t>(kMaxReliableMessageBytes + 1), kT0));
  server->update(kT0 + kMs);
  exchange(*alice, kAlice, kT0 + kMs);
  client_events(*alice);
  // The client acks with its next packet; once acked the queue has room again.
  alice->update(kT0 + 200 * kMs);
  server->update(kT0 + 200 * kMs);
  exchange(*alice, kAlice, kT0 + 200 * kMs);
  for (std::uint8_t i = 4; i < 8; ++i) {
    ASSERT_TRUE(server->send_reliable(id, std::vector<std::uint8_t>{i}, kT0 + 200 * kMs));
  }
  server->update(kT0 + 201 * kMs);
  exchange(*alice, kAlice, kT0 + 201 * kMs);
  std::vector<std::uint8_t> received;
  for (const ClientEvent& event : client_events(*alice)) {
    if (const auto* reliable = std::get_if<ClientReliable>(&event))
      received.push_back(reliable->bytes[0]);
  }
  EXPECT_EQ(received, (std::vector<std::uint8_t>{4, 5, 6, 7}));
  // Now the client goes silent: four more unacked messages fill the queue, the fifth disconnects.
  server_out();
  EXPECT_FALSE(server->send_reliable(id, std::vector<std::uint8_t>{9}, kT0 + 202 * kMs));
  EXPECT_FALSE(server->connected(id));
  auto events = server_events();
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(std::get<ServerDisconnected>(events[0]).reason, DisconnectReason::ReliableOverflow);
}

TEST_F(TransportTest, ABacklogOfDroppableMessagesIsDroppedAndCountedNeverDisconnecting) {
  GameServerConfig config = sim::test_server_config();
  config.max_reliable_pending = 8;
  config.max_reliable_queued = 64;
  start(config);
  auto alice = connected_client(7, kAlice, kT0);
  const ClientId id = connected_id(server_events());
  // A flood of chat while alice is behind: four fit (half the window), the rest are dropped.
  int queued = 0;
  for (int i = 0; i < 300; ++i) {
    const std::vector<std::uint8_t> chat{0xC0, static_cast<std::uint8_t>(i)};
    queued += server->send_reliable(id, chat, kT0, Delivery::Droppable) ? 1 : 0;
  }
  EXPECT_EQ(queued, 4);
  EXPECT_EQ(server->counters().reliable_dropped, 296u);
  // Must-arrive events still queue, past the window, and none is lost.
  for (std::uint8_t i = 0; i < 20; ++i) {
    ASSERT_TRUE(server->send_reliable(id, std::vector<std::uint8_t>{0xE0, i}, kT0));
  }
  EXPECT_TRUE(server->connected(id));
  EXPECT_TRUE(server_events().empty());
  std::vector<std::vector<std::uint8_t>> received;
  for (int round = 1; round <= 10; ++round) {
    const TimeUs now = kT0 + round * 200 * kMs;
    server->update(now);
    exchange(*alice, kAlice, now);
    alice->update(now);
    exchange(*alice, kAlice, now);
    for (const ClientEvent& event : client_events(*alice)) {
      if (const auto* reliable = std::get_if<ClientReliable>(&event))
        received.push_back(reliable->bytes);
    }
  }
  ASSERT_EQ(received.size(), 24u);
  for (std::uint8_t i = 0; i < 4; ++i) EXPECT_EQ(received[i], (std::vector<std::uint8_t>{0xC0, i}));
  for (std::uint8_t i = 0; i < 20; ++i) {
    EXPECT_EQ(received[4 + i], (std::vector<std::uint8_t>{0xE0, i}));
  }
  EXPECT_TRUE(server->connected(id));
  EXPECT_EQ(
      server->counters().disconnects[static_cast<std::size_t>(DisconnectReason::ReliableOverflow)],
      0u);
}

TEST_F(TransportTest, UnreliablePayloadsAreLimitedToOnePacket) {
  auto alice = connected_client(7, kAlice, kT0);
  const ClientId id = connected_id(server_events());
  server_out();
  EXPECT_TRUE(server->send_unreliable(id, std::vector<std::uint8_t>(kMaxUnreliableBytes, 1), kT0));
  auto packets = server_out();
  ASSERT_EQ(packets.size(), 1u);
  EXPECT_EQ(packets[0].bytes.size(), kMaxDatagramBytes);
  EXPECT_FALSE(
      server->send_unreliable(id, std::vector<std::uint8_t>(kMaxUnreliableBytes + 1, 1), kT0));
  EXPECT_FALSE(server->send_unreliable(9999, std::vector<std::uint8_t>{1}, kT0));
}

// poll_transmit swaps buffers: a caller that keeps its Transmit gets back, two packets later, the
// buffer it handed in, so a steady stream of payloads allocates nothing; every packet still
// opens at the client with its own bytes.
TEST_F(TransportTest, PolledTransmitsHandTheirBuffersBackForLaterPackets) {
  auto alice = connected_client(7, kAlice, kT0);
  const ClientId id = connected_id(server_events());
  server_out();
  client_events(*alice);
  Transmit kept;
  std::vector<const std::uint8_t*> buffers;
  for (std::uint8_t n = 1; n <= 6; ++n) {
    ASSERT_TRUE(server->send_unreliable(id, std::vector<std::uint8_t>(100, n), kT0));
    ASSERT_TRUE(server->poll_transmit(kept));
    EXPECT_FALSE(server->poll_transmit(kept)) << "one packet per payload";
    buffers.push_back(kept.bytes.data());
    EXPECT_EQ(kept.to, kAlice);
    alice->receive(kServerAddress, kept.bytes, kT0);
    auto events = client_events(*alice);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(std::get<ClientUnreliable>(events[0]).bytes, std::vector<std::uint8_t>(100, n));
  }
  // The first packet's buffer went back into the queue at the second poll (the second's came
  // fresh); from then on the two alternate.
  EXPECT_EQ(buffers[2], buffers[0]);
  EXPECT_EQ(buffers[3], buffers[1]);
  EXPECT_EQ(buffers[4], buffers[0]);
  EXPECT_NE(buffers[0], buffers[1]);
}

TEST(GameServerConfig, ValidateNamesTheFieldTheRangeAndWhatCame) {
  GameServerConfig config = sim::test_server_config();
  EXPECT_EQ(config.validate(), "");
  config.max_clients = 0;
  EXPECT_NE(config.validate().find("max_clients must be"), std::string::npos);
  EXPECT_NE(config.validate().find("got 0"), std::string::npos);
  EXPECT_THROW(GameServer{config}, std::invalid_argument);
}

}  // namespace
}  // namespace ricochet::proto::test::game_server_test
