/// Client and server over the deterministic simulated network: loss, latency, jitter,
/// duplication and reordering.
#include "net_sim.h"

#include <gtest/gtest.h>

#include <map>
#include <set>
#include <string>

namespace ricochet::proto::sim::net_sim_test {
namespace {

constexpr TimeUs kMs = kMicrosPerMilli;

const LinkConditions kBadMobile = {200 * kMs, 50 * kMs, 0.20, 0.05, 0.10, 30 * kMs};

/// The numbers (see numbered) carried by the client's events of one kind, in arrival order.
template <class Event>
std::vector<int> payloads(const std::vector<ClientEvent>& events) {
  std::vector<int> out;
  for (const ClientEvent& event : events) {
    if (const auto* e = std::get_if<Event>(&event)) {
      out.push_back(e->bytes.size() == 2 ? e->bytes[0] | (e->bytes[1] << 8) : -1);
    }
  }
  return out;
}

std::vector<std::uint8_t> numbered(int i) {
  return {static_cast<std::uint8_t>(i), static_cast<std::uint8_t>(i >> 8)};
}

/// 20 s of a server sending one unreliable and, every 10th tick, one reliable message to each
/// client at 20 Hz, clients answering with inputs at 20 Hz.
struct TrafficRun {
  explicit TrafficRun(std::uint64_t seed, LinkConditions conditions, int clients)
      : world(seed, conditions) {
    for (int i = 0; i < clients; ++i) world.add_client(client_address(i), 100 + i, 1, 0);
  }
  void play(TimeUs duration) {
    int tick = 0;
    for (TimeUs t = kMs; t <= duration; t += kMs) {
      world.step(t);
      if (t % (50 * kMs) != 0) continue;
      for (const ServerEvent& event : world.server_events) {
        if (const auto* connected = std::get_if<ServerConnected>(&event)) {
          ids.push_back(connected->client);
          id_of[connected->address.to_string()] = connected->client;
        }
      }
      world.server_events.clear();
      for (ClientId id : ids) {
        world.server.send_unreliable(id, numbered(tick), t);
        if (tick % 10 == 0) world.server.send_reliable(id, numbered(reliable_sent[id]++), t);
      }
      for (auto& peer : world.peers) peer.client->send_unreliable(numbered(tick), t);
      ++tick;
      world.drain(t);
    }
    unreliable_sent = tick;
  }
  SimWorld world;
  std::vector<ClientId> ids;
  std::map<std::string, ClientId> id_of;  ///< by client address
  std::map<ClientId, int> reliable_sent;  ///< per client: the next number
  int unreliable_sent = 0;
};

TEST(NetSim, SameSeedSameRun) {
  TrafficRun a(7, kBadMobile, 3), b(7, kBadMobile, 3);
  a.play(5 * kMicrosPerSecond);
  b.play(5 * kMicrosPerSecond);
  EXPECT_EQ(a.world.net.sent(), b.world.net.sent());
  EXPECT_EQ(a.world.net.lost(), b.world.net.lost());
  for (std::size_t i = 0; i < a.world.peers.size(); ++i) {
    EXPECT_EQ(payloads<ClientUnreliable>(a.world.peers[i].events),
              payloads<ClientUnreliable>(b.world.peers[i].events));
  }
  EXPECT_EQ(a.world.server.counters().drops, b.world.server.counters().drops);
}

TEST(NetSim, ConnectsAndDeliversReliablesInOrderOnceAt20PercentLoss200msAndJitter) {
  TrafficRun run(1234, kBadMobile, 4);
  run.play(20 * kMicrosPerSecond);
  EXPECT_GT(run.world.net.lost(), run.world.net.sent() / 10);
  EXPECT_GT(run.world.net.duplicated(), 0u);
  ASSERT_EQ(run.ids.size(), 4u);
  for (auto& peer : run.world.peers) {
    ASSERT_EQ(peer.client->state(), ConnectionState::Connected);
    // Reliables: all but those still in flight at the end (at most ~1 s of them), in order, once.
    const auto reliable = payloads<ClientReliable>(peer.events);
    const int sent = run.reliable_sent.at(run.id_of.at(peer.address.to_string()));
    EXPECT_GE(sent, 35);
    ASSERT_GE(static_cast<int>(reliable.size()), sent - 3);
    for (std::size_t i = 0; i < reliable.size(); ++i) EXPECT_EQ(reliable[i], static_cast<int>(i));
    // Unreliables: about 80 % arrive, never twice.
    const auto unreliable = payloads<ClientUnreliable>(peer.events);
    EXPECT_GT(unreliable.size(), static_cast<std::size_t>(run.unreliable_sent) * 6 / 10);
    std::set<int> unique(unreliable.begin(), unreliable.end());
    EXPECT_EQ(unique.size(), unreliable.size());
    EXPECT_GT(peer.client->counters().dropped(DropReason::Replayed), 0u) << "duplicates refused";
    EXPECT_GT(peer.client->rtt_us(), 300 * kMs);
    EXPECT_LT(peer.client->rtt_us(), 600 * kMs);
    // The server's packets by sequence: about a fifth never came, and jitter reordered some.
    const GameClient::ReceiveStats received = peer.client->receive_stats();
    EXPECT_GT(received.sent, 100u);
    const double loss = static_cast<double>(received.missing) / static_cast<double>(received.sent);
    EXPECT_GT(loss, 0.12);
    EXPECT_LT(loss, 0.28);
    EXPECT_GT(received.late, 0u);
  }
  EXPECT_EQ(run.world.server.counters().dropped(DropReason::ForgedMac), 0u);
  EXPECT_EQ(run.world.server.counters().connected, 4u);
}

TEST(NetSim, ACutLinkTimesOutBothEnds) {
  TrafficRun run(99, {20 * kMs, 0, 0.0, 0.0, 0.0, 0}, 1);
  run.play(kMicrosPerSecond);
  ASSERT_EQ(run.world.server.client_count(), 1u);
  run.world.net.set_conditions({20 * kMs, 0, 1.0, 0.0, 0.0, 0});
  run.world.run_until(kMicrosPerSecond + 5 * kMicrosPerSecond + 100 * kMs);
  EXPECT_EQ(run.world.server.client_count(), 0u);
  EXPECT_EQ(run.world.peers[0].client->disconnect_reason(), DisconnectReason::TimedOut);
}

}  // namespace
}  // namespace ricochet::proto::sim::net_sim_test
