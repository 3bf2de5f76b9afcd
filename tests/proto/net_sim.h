#pragma once
/// A deterministic network simulator for the sans-IO game channel: every datagram between a
/// GameServer and its GameClients goes through a seeded random link with latency, jitter, loss,
/// duplication and reordering. Same seed, same conditions, same calls: same run, bit for bit.
/// SimWorld wires one server and any number of clients together and advances them in steps of
/// fake time. Shared by the transport tests and the lead's end-to-end test.

#include <cstdint>
#include <memory>
#include <queue>
#include <random>
#include <vector>

#include "ricochet/proto/address.h"
#include "ricochet/proto/clock.h"
#include "ricochet/proto/connect_token.h"
#include "ricochet/proto/game_client.h"
#include "ricochet/proto/game_server.h"

namespace ricochet::proto::sim {

struct LinkConditions {
  TimeUs latency_us = 0;   ///< one way
  TimeUs jitter_us = 0;    ///< uniform in [-jitter, +jitter] added to the latency, ≥ 0 total
  double loss = 0.0;       ///< probability a datagram is lost, 0..1
  double duplicate = 0.0;  ///< probability a datagram is delivered twice, 0..1
  double reorder = 0.0;    ///< probability a datagram is held back by reorder_delay_us
  TimeUs reorder_delay_us = 0;
};

struct Datagram {
  Address from;
  Address to;
  std::vector<std::uint8_t> bytes;
};

class NetSim {
 public:
  NetSim(std::uint64_t seed, LinkConditions conditions) : rng_(seed), conditions_(conditions) {}

  void set_conditions(LinkConditions conditions) { conditions_ = conditions; }

  void send(const Address& from, const Address& to, std::vector<std::uint8_t> bytes, TimeUs now) {
    ++sent_;
    if (chance(conditions_.loss)) {
      ++lost_;
      return;
    }
    const int copies = chance(conditions_.duplicate) ? 2 : 1;
    if (copies == 2) ++duplicated_;
    for (int copy = 0; copy < copies; ++copy) {
      TimeUs delay = conditions_.latency_us;
      if (conditions_.jitter_us > 0) {
        delay += static_cast<TimeUs>(uniform() * static_cast<double>(2 * conditions_.jitter_us)) -
                 conditions_.jitter_us;
      }
      if (chance(conditions_.reorder)) delay += conditions_.reorder_delay_us;
      in_flight_.push({now + std::max<TimeUs>(delay, 0), order_++, {from, to, bytes}});
    }
  }

  /// The next datagram due at or before `now`, in delivery-time order.
  bool pop_due(TimeUs now, Datagram& out) {
    if (in_flight_.empty() || in_flight_.top().deliver_at > now) return false;
    out = in_flight_.top().datagram;
    in_flight_.pop();
    ++delivered_;
    return true;
  }

  std::uint64_t sent() const { return sent_; }
  std::uint64_t lost() const { return lost_; }
  std::uint64_t duplicated() const { return duplicated_; }
  std::uint64_t delivered() const { return delivered_; }

 private:
  struct InFlight {
    TimeUs deliver_at;
    std::uint64_t order;  ///< ties keep send order
    Datagram datagram;
    bool operator>(const InFlight& other) const {
      return deliver_at != other.deliver_at ? deliver_at > other.deliver_at : order > other.order;
    }
  };
  /// [0, 1) from the top 53 bits: the same on every standard library (unlike distributions).
  double uniform() { return static_cast<double>(rng_() >> 11) * 0x1.0p-53; }
  bool chance(double probability) { return probability > 0.0 && uniform() < probability; }

  std::mt19937_64 rng_;
  LinkConditions conditions_;
  std::priority_queue<InFlight, std::vector<InFlight>, std::greater<>> in_flight_;
  std::uint64_t order_ = 0;
  std::uint64_t sent_ = 0, lost_ = 0, duplicated_ = 0, delivered_ = 0;
};

inline constexpr std::uint64_t kTestProtocolId = 0x52494330'00000001ull;

/// A fixed token key so that runs repeat; the session keys inside tokens are still random.
inline Key test_token_key() {
  Key key{};
  for (std::size_t i = 0; i < key.size(); ++i) key[i] = static_cast<std::uint8_t>(0xA0 + i);
  return key;
}

inline GameServerConfig test_server_config() {
  GameServerConfig config;
  config.protocol_id = kTestProtocolId;
  config.token_key = test_token_key();
  return config;
}

inline Address client_address(int index) {
  return Address::ipv4(10, 0, static_cast<std::uint8_t>(index / 250),
                       static_cast<std::uint8_t>(index % 250 + 1), 40000);
}
inline const Address kServerAddress = Address::ipv4(10, 9, 9, 9, 7778);

inline ClientConnectInfo connect_info(std::uint64_t account_id, std::uint32_t match_id, TimeUs now,
                                      TimeUs lifetime_us = 30 * kMicrosPerSecond,
                                      std::uint32_t timeout_s = 5) {
  return {issue_connect_token(test_token_key(), kTestProtocolId, account_id, match_id, now,
                              lifetime_us, timeout_s),
          kTestProtocolId, kServerAddress};
}

/// One server and its clients on one NetSim.
class SimWorld {
 public:
  struct Peer {
    Address address;
    std::unique_ptr<GameClient> client;
    std::vector<ClientEvent> events;
  };

  SimWorld(std::uint64_t seed, LinkConditions conditions,
           GameServerConfig config = test_server_config())
      : server(std::move(config)), net(seed, conditions) {}

  /// Adds a client at `address` connecting with a fresh token for `account_id`; its index.
  std::size_t add_client(const Address& address, std::uint64_t account_id, std::uint32_t match_id,
                         TimeUs now_us, GameClientConfig config = {}) {
    peers.push_back({address,
                     std::make_unique<GameClient>(connect_info(account_id, match_id, now_us),
                                                  now_us, std::move(config)),
                     {}});
    drain(now_us);
    return peers.size() - 1;
  }

  /// Updates every endpoint at `now_us`, then delivers every datagram due by then.
  void step(TimeUs now_us) {
    now = now_us;
    for (Peer& peer : peers) peer.client->update(now_us);
    server.update(now_us);
    drain(now_us);
    Datagram datagram;
    while (net.pop_due(now_us, datagram)) {
      if (datagram.to == kServerAddress) {
        server.receive(datagram.from, datagram.bytes, now_us);
      } else {
        for (Peer& peer : peers) {
          if (peer.address == datagram.to)
            peer.client->receive(datagram.from, datagram.bytes, now_us);
        }
      }
      drain(now_us);
    }
  }

  /// Steps every step_us until `until_us` (inclusive).
  void run_until(TimeUs until_us, TimeUs step_us = kMicrosPerMilli) {
    for (TimeUs t = now + step_us; t <= until_us; t += step_us) step(t);
  }

  /// Moves every queued transmit into the network and every event into the logs.
  void drain(TimeUs now_us) {
    Transmit transmit;
    while (server.poll_transmit(transmit)) {
      net.send(kServerAddress, transmit.to, std::move(transmit.bytes), now_us);
    }
    ServerEvent server_event;
    while (server.poll_event(server_event)) server_events.push_back(std::move(server_event));
    for (Peer& peer : peers) {
      while (peer.client->poll_transmit(transmit)) {
        net.send(peer.address, transmit.to, std::move(transmit.bytes), now_us);
      }
      ClientEvent client_event;
      while (peer.client->poll_event(client_event)) peer.events.push_back(std::move(client_event));
    }
  }

  GameServer server;
  NetSim net;
  std::vector<Peer> peers;
  std::vector<ServerEvent> server_events;
  TimeUs now = 0;
};

}  // namespace ricochet::proto::sim
