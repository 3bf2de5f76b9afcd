/// The handshake and every rejection path of the server's receive, in-process (sans-IO).
#include <gtest/gtest.h>

#include "ricochet/proto/connect_token.h"
#include "ricochet/proto/crypto.h"
#include "transport_fixture.h"

namespace ricochet::proto::test::handshake_test {
namespace {

const Address kAlice = Address::ipv4(192, 0, 2, 10, 5000);
const Address kMallory = Address::ipv4(198, 51, 100, 66, 6666);
constexpr TimeUs kT0 = 100 * kMicrosPerSecond;

TEST_F(TransportTest, HandshakeConnectsBothEndsAndEveryReplyIsSmallerThanItsCause) {
  std::vector<StateTransition> client_transitions;
  GameClientConfig client_config;
  client_config.log.on_transition = [&](const StateTransition& t) {
    client_transitions.push_back(t);
  };
  GameClient client(sim::connect_info(77, 3, kT0), kT0, client_config);

  auto request = client_out(client);
  ASSERT_EQ(request.size(), 1u);
  EXPECT_EQ(request[0].to, kServerAddress);
  EXPECT_EQ(request[0].bytes.size(), kConnectionRequestBytes);
  server->receive(kAlice, request[0].bytes, kT0);
  auto challenge = server_out();
  ASSERT_EQ(challenge.size(), 1u);
  EXPECT_EQ(challenge[0].to, kAlice);
  EXPECT_LT(challenge[0].bytes.size(), request[0].bytes.size());
  EXPECT_EQ(server->counters().half_open, 1u);

  client.receive(kServerAddress, challenge[0].bytes, kT0);
  EXPECT_EQ(client.state(), ConnectionState::SendingResponse);
  auto response = client_out(client);
  ASSERT_EQ(response.size(), 1u);
  server->receive(kAlice, response[0].bytes, kT0);
  auto keep_alive = server_out();
  ASSERT_EQ(keep_alive.size(), 1u);
  EXPECT_LT(keep_alive[0].bytes.size(), response[0].bytes.size());

  client.receive(kServerAddress, keep_alive[0].bytes, kT0);
  EXPECT_EQ(client.state(), ConnectionState::Connected);
  auto events = server_events();
  ASSERT_EQ(events.size(), 1u);
  const auto* connected = std::get_if<ServerConnected>(&events[0]);
  ASSERT_NE(connected, nullptr);
  EXPECT_EQ(connected->account_id, 77u);
  EXPECT_EQ(connected->match_id, 3u);
  EXPECT_EQ(connected->address, kAlice);
  EXPECT_TRUE(server->connected(connected->client));
  EXPECT_EQ(server->counters().connected, 1u);
  EXPECT_EQ(server->counters().half_open, 0u);
  EXPECT_EQ(server->counters().dropped_total(), 0u);
  auto client_side = client_events(client);
  ASSERT_EQ(client_side.size(), 1u);
  EXPECT_TRUE(std::holds_alternative<ClientConnected>(client_side[0]));

  ASSERT_EQ(server_transitions.size(), 2u);
  EXPECT_EQ(server_transitions[0].from, ConnectionState::Connecting);
  EXPECT_EQ(server_transitions[0].to, ConnectionState::Challenged);
  EXPECT_EQ(server_transitions[1].to, ConnectionState::Connected);
  EXPECT_EQ(server_transitions[1].client, connected->client);
  ASSERT_EQ(client_transitions.size(), 3u);
  EXPECT_EQ(client_transitions[0].to, ConnectionState::SendingRequest);
  EXPECT_EQ(client_transitions[1].to, ConnectionState::SendingResponse);
  EXPECT_EQ(client_transitions[2].to, ConnectionState::Connected);
}

TEST_F(TransportTest, IPv6ClientsConnectAndDropsAreReportedThroughTheLog) {
  std::vector<std::pair<DropReason, Address>> dropped;
  GameServerConfig config = sim::test_server_config();
  config.log.on_drop = [&](DropReason reason, const Address& from) {
    dropped.emplace_back(reason, from);
  };
  start(config);
  Address v6;
  v6.v6 = true;
  v6.ip = {0x20, 0x01, 0x0d, 0xb8, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1};
  v6.port = 443;
  auto client = connected_client(8, v6, kT0);
  EXPECT_EQ(server->client_count(), 1u);
  server->receive(v6, std::vector<std::uint8_t>(40, 0xEE), kT0);
  ASSERT_EQ(dropped.size(), 1u);
  EXPECT_EQ(dropped[0].first, DropReason::Malformed);
  EXPECT_EQ(dropped[0].second, v6);
  EXPECT_EQ(name(dropped[0].first), "malformed");
}

TEST_F(TransportTest, LostChallengeAndLostKeepAliveAreRecoveredByResends) {
  GameClient client(sim::connect_info(5, 1, kT0), kT0);
  server->receive(kAlice, client_out(client)[0].bytes, kT0);
  server_out();  // the challenge is lost
  client.update(kT0 + 100 * kMicrosPerMilli);
  auto again = client_out(client);
  ASSERT_EQ(again.size(), 1u);
  EXPECT_EQ(again[0].bytes.size(), kConnectionRequestBytes);
  server->receive(kAlice, again[0].bytes, kT0 + 100 * kMicrosPerMilli);
  auto challenge = server_out();
  ASSERT_EQ(challenge.size(), 1u) << "the same token from the same address: challenge resent";
  client.receive(kServerAddress, challenge[0].bytes, kT0 + 100 * kMicrosPerMilli);
  server->receive(kAlice, client_out(client)[0].bytes, kT0 + 100 * kMicrosPerMilli);
  server_out();  // the keep-alive is lost
  client.update(kT0 + 200 * kMicrosPerMilli);
  auto response = client_out(client);
  ASSERT_EQ(response.size(), 1u);
  server->receive(kAlice, response[0].bytes, kT0 + 200 * kMicrosPerMilli);
  auto keep_alive = server_out();
  ASSERT_EQ(keep_alive.size(), 1u) << "a response from a connected client gets a keep-alive";
  client.receive(kServerAddress, keep_alive[0].bytes, kT0 + 200 * kMicrosPerMilli);
  EXPECT_EQ(client.state(), ConnectionState::Connected);
  EXPECT_EQ(server->counters().dropped_total(), 0u);
}

TEST_F(TransportTest, RefusesEmptyOversizedTruncatedAndUnknownTypes) {
  server->receive(kMallory, {}, kT0);
  EXPECT_EQ(drops(DropReason::Empty), 1u);
  server->receive(kMallory, std::vector<std::uint8_t>(kMaxDatagramBytes + 1, 0), kT0);
  EXPECT_EQ(drops(DropReason::Oversized), 1u);
  server->receive(kMallory, std::vector<std::uint8_t>(kConnectionRequestBytes - 1, 0), kT0);
  server->receive(kMallory,
                  std::vector<std::uint8_t>{static_cast<std::uint8_t>(PacketType::Payload), 1, 2},
                  kT0);
  EXPECT_EQ(drops(DropReason::Truncated), 2u);
  server->receive(kMallory, std::vector<std::uint8_t>(100, 0xEE), kT0);
  EXPECT_EQ(drops(DropReason::Malformed), 1u);
  EXPECT_TRUE(server_out().empty());
}

TEST_F(TransportTest, RefusesWrongVersionAndWrongProtocol) {
  const auto info = sim::connect_info(1, 1, kT0);
  auto request = write_connection_request(kTestProtocolId, info.grant.connect_token);
  request[3] ^= 0x20;
  server->receive(kMallory, request, kT0);
  EXPECT_EQ(drops(DropReason::WrongVersion), 1u);
  server->receive(kMallory, write_connection_request(kTestProtocolId + 1, info.grant.connect_token),
                  kT0);
  EXPECT_EQ(drops(DropReason::WrongProtocol), 1u);
  EXPECT_TRUE(server_out().empty());
}

// An ack header before anything was accepted would read as an ack of sequence 0. Neither end
// sends one: the client's first ack-bearing packet follows the keep-alive or payload that
// connected it, the server's follows the response it accepted; and each end's sequence 0 (the
// client's first response, the server's first keep-alive) carries no reliable message.
TEST_F(TransportTest, EveryAckHeaderNamesAPacketItsSenderAccepted) {
  const ClientConnectInfo info = sim::connect_info(5, 1, kT0);
  GameClient client(info, kT0);
  server->receive(kAlice, client_out(client)[0].bytes, kT0);
  client.receive(kServerAddress, server_out()[0].bytes, kT0);
  ASSERT_EQ(client.state(), ConnectionState::SendingResponse);
  // Messages queued before the connection wait for it; leaving now sends nothing.
  ASSERT_TRUE(client.send_reliable(std::vector<std::uint8_t>{1, 2, 3}, kT0));
  const auto response = client_out(client);
  ASSERT_EQ(response.size(), 1u);
  EXPECT_EQ(response[0].bytes[0], static_cast<std::uint8_t>(PacketType::Response));
  EXPECT_EQ(read_encrypted_header(response[0].bytes).value.sequence, 0u);

  server->receive(kAlice, response[0].bytes, kT0);
  const auto keep_alive = server_out();
  ASSERT_EQ(keep_alive.size(), 1u);
  const auto header = read_encrypted_header(keep_alive[0].bytes);
  ASSERT_TRUE(header.ok());
  EXPECT_EQ(header.value.type, PacketType::KeepAlive);
  EXPECT_EQ(header.value.sequence, 0u);
  std::vector<std::uint8_t> body;
  ASSERT_TRUE(open_packet(keep_alive[0].bytes, kTestProtocolId, info.grant.server_to_client, body));
  const auto ack = read_keep_alive_body(body);
  ASSERT_TRUE(ack.ok());
  EXPECT_EQ(ack.value, (AckHeader{0, 0}));  // names the response, which the server accepted

  client.receive(kServerAddress, keep_alive[0].bytes, kT0);
  ASSERT_EQ(client.state(), ConnectionState::Connected);
  client.update(kT0 + kMicrosPerSecond / 100);
  const auto first = client_out(client);
  ASSERT_FALSE(first.empty());
  const auto payload_header = read_encrypted_header(first[0].bytes);
  EXPECT_EQ(payload_header.value.type, PacketType::Payload);  // the queued message, sequence 1
  EXPECT_EQ(payload_header.value.sequence, 1u);

  GameClient early(sim::connect_info(6, 1, kT0), kT0);
  server->receive(kMallory, client_out(early)[0].bytes, kT0);
  early.receive(kServerAddress, server_out()[0].bytes, kT0);
  ASSERT_EQ(early.state(), ConnectionState::SendingResponse);
  ASSERT_EQ(client_out(early).size(), 1u);  // its response
  early.disconnect(kT0);
  EXPECT_TRUE(client_out(early).empty()) << "nothing accepted yet: no disconnect packet";
}

TEST_F(TransportTest, RefusesARequestWhosePaddingIsNotZeroWithoutAnswering) {
  const auto info = sim::connect_info(1, 1, kT0);
  auto request = write_connection_request(kTestProtocolId, info.grant.connect_token);
  request.back() = 0xFF;
  server->receive(kMallory, request, kT0);
  EXPECT_EQ(drops(DropReason::Malformed), 1u);
  EXPECT_TRUE(server_out().empty());
  EXPECT_EQ(server->counters().half_open, 0u);
}

TEST_F(TransportTest, RefusesForgedExpiredAndMalformedTokens) {
  auto info = sim::connect_info(1, 1, kT0, 2 * kMicrosPerSecond);
  auto forged = info.grant.connect_token;
  forged[40] ^= 1;
  server->receive(kMallory, write_connection_request(kTestProtocolId, forged), kT0);
  EXPECT_EQ(drops(DropReason::TokenInvalid), 1u);
  const auto foreign =
      issue_connect_token(random_key(), kTestProtocolId, 1, 1, kT0, kMicrosPerSecond, 5);
  server->receive(Address::ipv4(1, 1, 1, 1, 1),
                  write_connection_request(kTestProtocolId, foreign.connect_token), kT0);
  EXPECT_EQ(drops(DropReason::TokenInvalid), 2u) << "sealed under another server's key";
  server->receive(Address::ipv4(1, 1, 1, 2, 1),
                  write_connection_request(kTestProtocolId, info.grant.connect_token),
                  kT0 + 2 * kMicrosPerSecond);
  EXPECT_EQ(drops(DropReason::TokenExpired), 1u);
  EXPECT_TRUE(server_out().empty());
}

TEST_F(TransportTest, ATokenIsUsableFromOneAddressOnlyAndOnlyUntilItConnected) {
  const auto info = sim::connect_info(9, 1, kT0);
  const auto request = write_connection_request(kTestProtocolId, info.grant.connect_token);
  server->receive(kAlice, request, kT0);
  ASSERT_EQ(server_out().size(), 1u);
  server->receive(kMallory, request, kT0);
  EXPECT_EQ(drops(DropReason::TokenReused), 1u);
  EXPECT_TRUE(server_out().empty()) << "the copy from another address gets nothing";

  const auto info2 = sim::connect_info(11, 1, kT0);
  const Address bob = Address::ipv4(203, 0, 113, 1, 1);
  GameClient client(info2, kT0);
  exchange(client, bob, kT0);
  ASSERT_EQ(client.state(), ConnectionState::Connected);
  client.disconnect(kT0);
  exchange(client, bob, kT0);
  server->receive(bob, write_connection_request(kTestProtocolId, info2.grant.connect_token), kT0);
  EXPECT_EQ(drops(DropReason::TokenReused), 2u) << "a token that connected once is spent";
}

TEST_F(TransportTest, ASpoofedSourceGetsOnlyAChallengeItCannotAnswer) {
  // Mallory holds a token and its keys but puts kAlice's address on her packets.
  const auto info = sim::connect_info(13, 1, kT0);
  server->receive(kAlice, write_connection_request(kTestProtocolId, info.grant.connect_token), kT0);
  auto challenge = server_out();
  ASSERT_EQ(challenge.size(), 1u);
  EXPECT_EQ(challenge[0].to, kAlice) << "the challenge goes to the claimed address, not to Mallory";
  // Without the challenge Mallory can only guess its body.
  ChallengeBody guess;
  guess.challenge_sequence = 0;
  fill_random(guess.challenge_token);
  server->receive(kAlice,
                  seal_packet(PacketType::Response, 0, kTestProtocolId, info.grant.client_to_server,
                              write_challenge_body(guess)),
                  kT0);
  EXPECT_EQ(drops(DropReason::ChallengeInvalid), 1u);
  server->receive(kMallory,
                  seal_packet(PacketType::Response, 1, kTestProtocolId, info.grant.client_to_server,
                              write_challenge_body(guess)),
                  kT0);
  EXPECT_EQ(drops(DropReason::UnknownAddress), 1u);
  EXPECT_TRUE(server_out().empty());
  EXPECT_EQ(server->client_count(), 0u);
}

TEST_F(TransportTest, ATokenOpensOneHandshakeSoARetryNeverReusesItsKeysAndNonces) {
  const auto info = sim::connect_info(14, 1, kT0);
  GameClient client(info, kT0);
  server->receive(kAlice, client_out(client)[0].bytes, kT0);
  client.receive(kServerAddress, server_out()[0].bytes, kT0);
  const auto old_response = client_out(client)[0].bytes;  // lost on its way
  server->update(kT0 + 5 * kMicrosPerSecond);             // the handshake times out
  EXPECT_EQ(server->counters().half_open, 0u);
  const TimeUs later = kT0 + 5 * kMicrosPerSecond;
  server->receive(kAlice, write_connection_request(kTestProtocolId, info.grant.connect_token),
                  later);
  EXPECT_TRUE(server_out().empty()) << "same token, same address, handshake over: no new one";
  EXPECT_EQ(drops(DropReason::TokenReused), 1u);
  server->receive(kAlice, old_response, later);
  EXPECT_EQ(drops(DropReason::UnknownAddress), 1u);
  EXPECT_EQ(server->client_count(), 0u);
  // A new token (JoinMatch again) connects from the same address.
  auto again = connected_client(14, kAlice, later);
  EXPECT_EQ(server->client_count(), 1u);
}

TEST_F(TransportTest, RefusesForgedMacsReplaysAndPacketsOutOfState) {
  const auto info = sim::connect_info(21, 1, kT0);
  GameClient client(info, kT0);
  server->receive(kAlice, client_out(client)[0].bytes, kT0);
  client.receive(kServerAddress, server_out()[0].bytes, kT0);
  auto response = client_out(client)[0].bytes;

  server->receive(kAlice,
                  seal_packet(PacketType::KeepAlive, 5, kTestProtocolId,
                              info.grant.client_to_server, write_keep_alive_body({})),
                  kT0);
  EXPECT_EQ(drops(DropReason::WrongState), 1u) << "keep-alive while challenged";
  auto forged = response;
  forged.back() ^= 1;
  server->receive(kAlice, forged, kT0);
  EXPECT_EQ(drops(DropReason::ForgedMac), 1u);
  server->receive(kAlice, response, kT0);
  ASSERT_EQ(server->client_count(), 1u);
  server->receive(kAlice, response, kT0);
  EXPECT_EQ(drops(DropReason::Replayed), 1u) << "the response replayed after connecting";
  server->receive(kAlice, write_connection_request(kTestProtocolId, info.grant.connect_token), kT0);
  EXPECT_EQ(drops(DropReason::WrongState), 2u) << "a request from a connected address";

  client.receive(kServerAddress, server_out()[0].bytes, kT0);
  ASSERT_TRUE(client.send_unreliable(std::vector<std::uint8_t>{1, 2, 3}, kT0));
  auto payload = client_out(client)[0].bytes;
  server->receive(kAlice, payload, kT0);
  server->receive(kAlice, payload, kT0);
  EXPECT_EQ(drops(DropReason::Replayed), 2u);
  auto events = server_events();
  ASSERT_EQ(events.size(), 2u);  // connected, one payload
  EXPECT_EQ(std::get<ServerUnreliable>(events[1]).bytes, (std::vector<std::uint8_t>{1, 2, 3}));
  EXPECT_EQ(std::get<ServerUnreliable>(events[1]).account_id,
            std::get<ServerConnected>(events[0]).account_id);
  EXPECT_EQ(std::get<ServerUnreliable>(events[1]).rtt_us,
            server->rtt_us(std::get<ServerConnected>(events[0]).client));
}

TEST_F(TransportTest, RateLimitsUnconnectedAddressesAndConnectedClients) {
  GameServerConfig config = sim::test_server_config();
  config.address_packets_per_s = 10;
  config.address_burst = 5;
  config.client_packets_per_s = 10;
  config.client_burst = 20;
  start(config);
  // Requests with a token that does not open: the only kind an unknown address is tracked for.
  const auto bad_request = write_connection_request(
      kTestProtocolId, std::vector<std::uint8_t>(kConnectTokenBytes, 0xEE));
  for (int i = 0; i < 8; ++i) server->receive(kMallory, bad_request, kT0);
  EXPECT_EQ(drops(DropReason::TokenInvalid), 5u);
  EXPECT_EQ(drops(DropReason::AddressRateLimited), 3u);
  server->receive(kMallory, bad_request, kT0 + 100 * kMicrosPerMilli);
  EXPECT_EQ(drops(DropReason::TokenInvalid), 6u) << "refilled at 10 per second";

  auto alice = connected_client(1, kAlice, kT0);
  auto events = server_events();
  const ClientId id = std::get<ServerConnected>(events[0]).client;
  for (int i = 0; i < 30; ++i) {
    ASSERT_TRUE(alice->send_unreliable(std::vector<std::uint8_t>{1}, kT0));
    server->receive(kAlice, client_out(*alice)[0].bytes, kT0);
  }
  EXPECT_GT(drops(DropReason::ClientRateLimited), 0u);
  EXPECT_LE(server_events().size(), 20u);
  EXPECT_TRUE(server->connected(id)) << "a flood is dropped, not a reason to disconnect";
}

TEST_F(TransportTest, CapsTrackedAddressesAndHalfOpenHandshakes) {
  GameServerConfig config = sim::test_server_config();
  config.max_tracked_addresses = 2;
  config.max_half_open = 1;
  start(config);
  const Address a = Address::ipv4(1, 0, 0, 1, 1), b = Address::ipv4(1, 0, 0, 2, 1),
                c = Address::ipv4(1, 0, 0, 3, 1);
  server->receive(
      a,
      write_connection_request(kTestProtocolId, sim::connect_info(1, 1, kT0).grant.connect_token),
      kT0);
  EXPECT_EQ(server->counters().half_open, 1u);
  server->receive(
      b,
      write_connection_request(kTestProtocolId, sim::connect_info(2, 1, kT0).grant.connect_token),
      kT0);
  EXPECT_EQ(drops(DropReason::HalfOpenCap), 1u);
  const auto bad_request = write_connection_request(
      kTestProtocolId, std::vector<std::uint8_t>(kConnectTokenBytes, 0xEE));
  server->receive(c, bad_request, kT0);
  EXPECT_EQ(drops(DropReason::AddressTableFull), 1u);
  EXPECT_EQ(server_out().size(), 1u);
  server->update(kT0 + 5 * kMicrosPerSecond);  // the half-open handshake times out
  EXPECT_EQ(server->counters().half_open, 0u);
  ASSERT_FALSE(server_transitions.empty());
  EXPECT_EQ(server_transitions.back().to, ConnectionState::Disconnected);
  EXPECT_EQ(server_transitions.back().reason, "handshake timed out");
  // That update also forgot the budgets of a and b, refilled by then: c is tracked now.
  server->receive(c, bad_request, kT0 + 5 * kMicrosPerSecond);
  EXPECT_EQ(drops(DropReason::AddressTableFull), 1u);
}

TEST_F(TransportTest, AFullServerDeniesWithAPacketOnlyTheTokenHolderCanRead) {
  GameServerConfig config = sim::test_server_config();
  config.max_clients = 1;
  start(config);
  auto first = connected_client(1, kAlice, kT0);
  GameClient second(sim::connect_info(2, 1, kT0), kT0);
  auto request = client_out(second);
  server->receive(kMallory, request[0].bytes, kT0);
  auto denied = server_out();
  ASSERT_EQ(denied.size(), 1u);
  EXPECT_LT(denied[0].bytes.size(), request[0].bytes.size());
  EXPECT_EQ(drops(DropReason::ServerFull), 1u);
  second.receive(kServerAddress, denied[0].bytes, kT0);
  EXPECT_EQ(second.state(), ConnectionState::Disconnected);
  EXPECT_EQ(second.disconnect_reason(), DisconnectReason::Denied);
  EXPECT_EQ(first->state(), ConnectionState::Connected);
}

TEST_F(TransportTest, ReliableMessagesFarAheadOfTheWindowAreDropped) {
  const auto info = sim::connect_info(3, 1, kT0);
  GameClient client(info, kT0);
  exchange(client, kAlice, kT0);
  ASSERT_EQ(client.state(), ConnectionState::Connected);
  PayloadBody body;
  body.reliable = {{1000, {1}}};
  server->receive(kAlice,
                  seal_packet(PacketType::Payload, 500, kTestProtocolId,
                              info.grant.client_to_server, write_payload_body(body)),
                  kT0);
  EXPECT_EQ(drops(DropReason::ReliableOutOfWindow), 1u);
}

TEST_F(TransportTest, TheClientDropsStrangersForgeriesAndPacketsOutOfState) {
  const auto info = sim::connect_info(4, 1, kT0);
  GameClient client(info, kT0);
  client_out(client);
  const auto keep_alive = seal_packet(PacketType::KeepAlive, 0, kTestProtocolId,
                                      info.grant.server_to_client, write_keep_alive_body({}));
  client.receive(kMallory, keep_alive, kT0);
  EXPECT_EQ(client.counters().dropped(DropReason::UnknownAddress), 1u);
  client.receive(kServerAddress, keep_alive, kT0);
  EXPECT_EQ(client.counters().dropped(DropReason::WrongState), 1u)
      << "keep-alive before a challenge";
  const auto forged_challenge =
      seal_packet(PacketType::Challenge, kHandshakeSequenceBit, kTestProtocolId, random_key(),
                  write_challenge_body({}));
  client.receive(kServerAddress, forged_challenge, kT0);
  EXPECT_EQ(client.counters().dropped(DropReason::ForgedMac), 1u);
  EXPECT_EQ(client.state(), ConnectionState::SendingRequest);
}

}  // namespace
}  // namespace ricochet::proto::test::handshake_test
