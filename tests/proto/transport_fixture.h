#pragma once
/// In-process driving of one GameServer and hand-made clients, without a network between them:
/// each test decides which datagram goes where, so every rejection path can be reached.

#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "net_sim.h"
#include "ricochet/proto/game_client.h"
#include "ricochet/proto/game_server.h"
#include "ricochet/proto/packet.h"

namespace ricochet::proto::test {

using sim::kServerAddress;
using sim::kTestProtocolId;

class TransportTest : public ::testing::Test {
 protected:
  void SetUp() override { start(sim::test_server_config()); }

  void start(GameServerConfig config) {
    config.log.on_transition = [this](const StateTransition& t) {
      server_transitions.push_back(t);
    };
    server = std::make_unique<GameServer>(std::move(config));
  }

  std::vector<Transmit> server_out() {
    std::vector<Transmit> out;
    Transmit transmit;
    while (server->poll_transmit(transmit)) out.push_back(std::move(transmit));
    return out;
  }
  static std::vector<Transmit> client_out(GameClient& client) {
    std::vector<Transmit> out;
    Transmit transmit;
    while (client.poll_transmit(transmit)) out.push_back(std::move(transmit));
    return out;
  }
  std::vector<ServerEvent> server_events() {
    std::vector<ServerEvent> out;
    ServerEvent event;
    while (server->poll_event(event)) out.push_back(std::move(event));
    return out;
  }
  static std::vector<ClientEvent> client_events(GameClient& client) {
    std::vector<ClientEvent> out;
    ClientEvent event;
    while (client.poll_event(event)) out.push_back(std::move(event));
    return out;
  }

  /// Delivers everything `client` queued to the server as coming from `from`, and everything
  /// the server sends to `from` back to the client, until both are quiet.
  void exchange(GameClient& client, const Address& from, TimeUs now) {
    for (int round = 0; round < 8; ++round) {
      bool moved = false;
      for (const Transmit& transmit : client_out(client)) {
        server->receive(from, transmit.bytes, now);
        moved = true;
      }
      for (const Transmit& transmit : server_out()) {
        if (transmit.to == from) client.receive(kServerAddress, transmit.bytes, now);
        moved = true;
      }
      if (!moved) return;
    }
  }

  /// A client for `account_id` that has completed its handshake from `from`.
  std::unique_ptr<GameClient> connected_client(std::uint64_t account_id, const Address& from,
                                               TimeUs now, std::uint32_t match_id = 1) {
    auto client = std::make_unique<GameClient>(sim::connect_info(account_id, match_id, now), now);
    exchange(*client, from, now);
    EXPECT_EQ(client->state(), ConnectionState::Connected);
    return client;
  }

  std::uint64_t drops(DropReason reason) const { return server->counters().dropped(reason); }

  std::unique_ptr<GameServer> server;
  std::vector<StateTransition> server_transitions;
};

}  // namespace ricochet::proto::test
