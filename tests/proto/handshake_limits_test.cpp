/// The server's limits on handshakes and tokens (PROTOCOL.md Game channel transport §2, §9,
/// §12), in-process with fake time: what an unknown address may make it remember, one
/// handshake per account, per-host caps, the used-token table's cap, and budgets spent only by
/// authenticated packets.
#include <gtest/gtest.h>

#include "ricochet/proto/connect_token.h"
#include "transport_fixture.h"

namespace ricochet::proto::test::handshake_limits_test {
namespace {

const Address kAlice = Address::ipv4(192, 0, 2, 10, 5000);
constexpr TimeUs kT0 = 100 * kMicrosPerSecond;

std::vector<std::uint8_t> request_of(const ClientConnectInfo& info) {
  return write_connection_request(kTestProtocolId, info.grant.connect_token);
}

TEST_F(TransportTest, OnlyADatagramShapedLikeARequestMakesAnUnknownAddressTracked) {
  GameServerConfig config = sim::test_server_config();
  config.max_tracked_addresses = 1;
  start(config);
  // A spoofed flood: 1-byte datagrams, encrypted-looking packets and short requests from many
  // addresses. None of them is remembered, so none fills the one-entry table.
  for (std::uint16_t port = 1; port <= 500; ++port) {
    const Address source = Address::ipv4(198, 51, 100, static_cast<std::uint8_t>(port % 200), port);
    server->receive(source, std::vector<std::uint8_t>{0x42}, kT0);
    server->receive(source, std::vector<std::uint8_t>(100, 0x05), kT0);
    server->receive(source, std::vector<std::uint8_t>(kConnectionRequestBytes - 1, 0), kT0);
  }
  EXPECT_EQ(drops(DropReason::Malformed), 500u);
  EXPECT_EQ(drops(DropReason::UnknownAddress), 500u);
  EXPECT_EQ(drops(DropReason::Truncated), 500u);
  auto wrong_version = request_of(sim::connect_info(2, 1, kT0));
  wrong_version[1] ^= 1;
  server->receive(Address::ipv4(198, 51, 100, 1, 9), wrong_version, kT0);
  EXPECT_EQ(drops(DropReason::WrongVersion), 1u);
  EXPECT_EQ(drops(DropReason::AddressTableFull), 0u);

  auto alice = connected_client(1, kAlice, kT0);
  EXPECT_EQ(server->client_count(), 1u) << "the victim's request found the table empty";
}

TEST_F(TransportTest, AnAccountHoldsOneHandshakeAndItsNewerTokenReplacesIt) {
  const Address first = Address::ipv4(192, 0, 2, 10, 1);
  const Address second = Address::ipv4(203, 0, 113, 7, 2);
  GameClient old_attempt(sim::connect_info(5, 1, kT0), kT0);
  server->receive(first, client_out(old_attempt)[0].bytes, kT0);
  old_attempt.receive(kServerAddress, server_out()[0].bytes, kT0);
  EXPECT_EQ(server->counters().half_open, 1u);

  GameClient new_attempt(sim::connect_info(5, 1, kT0), kT0);
  server->receive(second, client_out(new_attempt)[0].bytes, kT0);
  EXPECT_EQ(server->counters().half_open, 1u) << "one handshake per account";
  ASSERT_FALSE(server_transitions.empty());
  EXPECT_EQ(server_transitions[server_transitions.size() - 2].address, first);
  EXPECT_EQ(server_transitions[server_transitions.size() - 2].reason,
            "replaced by a newer token of its account");
  server->receive(first, client_out(old_attempt)[0].bytes, kT0);
  EXPECT_EQ(drops(DropReason::UnknownAddress), 1u) << "the replaced handshake is gone";
  new_attempt.receive(kServerAddress, server_out()[0].bytes, kT0);
  exchange(new_attempt, second, kT0);
  EXPECT_EQ(new_attempt.state(), ConnectionState::Connected);
  EXPECT_EQ(server->counters().half_open, 0u);
}

TEST_F(TransportTest, AnotherAccountsRequestCannotReplaceAHandshakeInProgress) {
  GameClient alice(sim::connect_info(1, 1, kT0), kT0);
  server->receive(kAlice, client_out(alice)[0].bytes, kT0);
  alice.receive(kServerAddress, server_out()[0].bytes, kT0);
  // Mallory's own valid token, sent with Alice's address as its source.
  server->receive(kAlice, request_of(sim::connect_info(66, 1, kT0)), kT0);
  EXPECT_EQ(drops(DropReason::HandshakeInProgress), 1u);
  EXPECT_TRUE(server_out().empty());
  exchange(alice, kAlice, kT0);
  EXPECT_EQ(alice.state(), ConnectionState::Connected);
}

TEST_F(TransportTest, HandshakesInProgressAreCappedPerHostAndAnIPv6HostIsItsSlash64) {
  GameServerConfig config = sim::test_server_config();
  config.max_half_open_per_host = 2;
  start(config);
  for (std::uint16_t account = 1; account <= 3; ++account) {
    server->receive(Address::ipv4(192, 0, 2, 10, account),
                    request_of(sim::connect_info(account, 1, kT0)), kT0);
  }
  EXPECT_EQ(server->counters().half_open, 2u);
  EXPECT_EQ(drops(DropReason::HostHalfOpenCap), 1u);
  server->receive(Address::ipv4(192, 0, 2, 11, 3), request_of(sim::connect_info(3, 1, kT0)), kT0);
  EXPECT_EQ(server->counters().half_open, 3u) << "another host has its own";

  Address v6;
  v6.v6 = true;
  v6.ip = {0x20, 0x01, 0x0d, 0xb8, 0, 0, 0, 7, 0, 0, 0, 0, 0, 0, 0, 1};
  for (std::uint8_t i = 0; i < 3; ++i) {
    v6.ip[15] = static_cast<std::uint8_t>(i + 1);  // other addresses in one /64
    server->receive(v6, request_of(sim::connect_info(100u + i, 1, kT0)), kT0);
  }
  EXPECT_EQ(drops(DropReason::HostHalfOpenCap), 2u);
  // The handshakes time out: the host's slots are free again.
  server->update(kT0 + 5 * kMicrosPerSecond);
  server->receive(Address::ipv4(192, 0, 2, 10, 9),
                  request_of(sim::connect_info(9, 1, kT0 + 5 * kMicrosPerSecond)),
                  kT0 + 5 * kMicrosPerSecond);
  EXPECT_EQ(server->counters().half_open, 1u);
}

TEST_F(TransportTest, ConnectionsAreCappedPerHostWithADeniedPacketThatSaysSo) {
  GameServerConfig config = sim::test_server_config();
  config.max_clients_per_host = 1;
  start(config);
  auto first = connected_client(1, Address::ipv4(192, 0, 2, 10, 1), kT0);
  const auto second_info = sim::connect_info(2, 1, kT0);
  GameClient second(second_info, kT0);
  exchange(second, Address::ipv4(192, 0, 2, 10, 2), kT0);
  EXPECT_EQ(second.state(), ConnectionState::Disconnected);
  EXPECT_EQ(second.disconnect_reason(), DisconnectReason::HostFull);
  EXPECT_EQ(drops(DropReason::HostFull), 1u);
  // The connected account coming back from the same host replaces itself: never denied.
  auto again = connected_client(1, Address::ipv4(192, 0, 2, 10, 3), kT0);
  EXPECT_EQ(server->client_count(), 1u);
  // Another host is not affected, and the denied request did not use its token up.
  GameClient elsewhere(second_info, kT0);
  exchange(elsewhere, Address::ipv4(192, 0, 2, 11, 2), kT0);
  EXPECT_EQ(elsewhere.state(), ConnectionState::Connected);
  EXPECT_EQ(server->client_count(), 2u);
}

TEST_F(TransportTest, TheUsedTokenTableHasAHardCapAndForgetsOnlyExpiredTokens) {
  GameServerConfig config = sim::test_server_config();
  config.max_used_tokens = 2;
  start(config);
  const TimeUs lifetime = 2 * kMicrosPerSecond;
  for (std::uint8_t i = 1; i <= 3; ++i) {
    server->receive(Address::ipv4(192, 0, 2, i, 1),
                    request_of(sim::connect_info(i, 1, kT0, lifetime)), kT0);
  }
  EXPECT_EQ(drops(DropReason::UsedTokenTableFull), 1u);
  EXPECT_EQ(server->counters().half_open, 2u);
  // The two tokens expire (and their handshakes, whose timeout is longer, stay): room again.
  server->update(kT0 + lifetime);
  server->receive(Address::ipv4(192, 0, 2, 3, 1),
                  request_of(sim::connect_info(3, 1, kT0 + lifetime)), kT0 + lifetime);
  EXPECT_EQ(server->counters().half_open, 3u);
  EXPECT_EQ(drops(DropReason::UsedTokenTableFull), 1u);
}

TEST_F(TransportTest, PacketsSpoofedWithAClientsAddressDoNotSpendItsBudget) {
  GameServerConfig config = sim::test_server_config();
  config.client_packets_per_s = 1;
  config.client_burst = 5;
  start(config);
  auto alice = connected_client(1, kAlice, kT0);
  server_events();
  std::vector<std::uint8_t> forged(64, 0xA5);
  forged[0] = static_cast<std::uint8_t>(PacketType::Payload);
  for (std::uint8_t i = 0; i < 100; ++i) {
    forged[1] = i;  // a sequence not seen yet
    server->receive(kAlice, forged, kT0);
  }
  EXPECT_EQ(drops(DropReason::ForgedMac), 100u);
  EXPECT_EQ(drops(DropReason::ClientRateLimited), 0u);
  for (int i = 0; i < 6; ++i) {
    ASSERT_TRUE(alice->send_unreliable(std::vector<std::uint8_t>{1}, kT0));
    server->receive(kAlice, client_out(*alice)[0].bytes, kT0);
  }
  EXPECT_EQ(server_events().size(), 5u) << "the client's own burst, all of it";
  EXPECT_EQ(drops(DropReason::ClientRateLimited), 1u) << "its own sixth packet";
}

}  // namespace
}  // namespace ricochet::proto::test::handshake_limits_test
