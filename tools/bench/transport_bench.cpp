/// Transport bench: what the server end of the game channel (proto/game_server.h) costs per
/// datagram, without sockets or a kernel: N clients (proto::GameClient) connected in memory to
/// one proto::GameServer. Each tick every client sends an input-sized unreliable payload, the
/// server takes them all (receive, then its events, as the game channel drains them), then sends
/// every client a snapshot-sized payload (send_unreliable, then its transmits); the clients take
/// theirs, which acknowledges the server's packets in their next ones. update() runs every 10 ms,
/// as the game channel calls it. Only the server's calls are timed, by this thread's CPU time;
/// the clients' work is not.
///
/// The figures are the transport's own share of the server's per-datagram cost in the capacity
/// benchmark (tools/bench/CAPACITY.md: decrypting, the ack windows, the client lookups,
/// allocations), with the working set of N clients, free of the loopback stack and of the
/// machine's noise.
///
///   transport-bench [--clients 64,256,1024] [--seconds 10] [--rate 60] [--input-bytes 48]
///                   [--snapshot-bytes 600] [--out FILE]

#include <CLI/CLI.hpp>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <unordered_map>
#include <variant>
#include <vector>

#include "harness.h"
#include "ricochet/proto/address.h"
#include "ricochet/proto/connect_token.h"
#include "ricochet/proto/game_client.h"
#include "ricochet/proto/game_server.h"

namespace proto = ricochet::proto;
namespace bench = ricochet::bench;

namespace {

struct BenchOptions {
  double seconds = 10;
  int rate_hz = 60;
  std::size_t input_bytes = 48;
  std::size_t snapshot_bytes = 600;
};

/// ns of this thread's CPU time since `start` (bench::thread_cpu_ns).
std::uint64_t cpu_ns_since(std::int64_t start) {
  return static_cast<std::uint64_t>(bench::thread_cpu_ns() - start);
}

const proto::Address kServerAddress = proto::Address::ipv4(10, 255, 255, 1, 7778);

proto::Address client_address(std::size_t index) {
  return proto::Address::ipv4(10, static_cast<std::uint8_t>(index / 62500),
                              static_cast<std::uint8_t>(index / 250 % 250),
                              static_cast<std::uint8_t>(index % 250 + 1), 40000);
}

proto::Key token_key() {
  proto::Key key{};
  for (std::size_t i = 0; i < key.size(); ++i) key[i] = static_cast<std::uint8_t>(0x5A ^ i);
  return key;
}

struct Peer {
  proto::Address address;
  std::unique_ptr<proto::GameClient> client;
  std::vector<std::vector<std::uint8_t>> inbox;  ///< the server's datagrams, not yet taken
};

struct Result {
  std::size_t clients = 0;
  std::uint64_t ticks = 0;
  std::uint64_t datagrams_in = 0, datagrams_out = 0, updates = 0;
  std::uint64_t receive_ns = 0, send_ns = 0, update_ns = 0;
  std::uint64_t payloads_delivered = 0;  ///< ServerUnreliable events
  std::uint64_t drops = 0;               ///< the server's, any reason
  std::uint64_t snapshots_taken = 0;     ///< payloads the clients received
};

class TransportBench {
 public:
  TransportBench(std::size_t clients, const BenchOptions& options)
      : options_(options), server_(server_config(clients)) {
    peers_.resize(clients);
    ids_.resize(clients);
    for (std::size_t k = 0; k < clients; ++k) {
      Peer& peer = peers_[k];
      peer.address = client_address(k);
      peer_of_[peer.address] = k;
      const proto::TokenGrant grant =
          proto::issue_connect_token(token_key(), proto::kProtocolId, kFirstAccount + k, 1, now_,
                                     30 * proto::kMicrosPerSecond, 10);
      peer.client = std::make_unique<proto::GameClient>(
          proto::ClientConnectInfo{grant, proto::kProtocolId, kServerAddress}, now_);
    }
  }

  /// Connects every client; false when some did not within a simulated second.
  bool connect() {
    for (int round = 0; round < 100; ++round) {
      now_ += 10 * proto::kMicrosPerMilli;
      for (Peer& peer : peers_) peer.client->update(now_);
      server_.update(now_);
      exchange();
      std::size_t connected = 0;
      for (const Peer& peer : peers_) {
        connected += peer.client->state() == proto::ConnectionState::Connected;
      }
      if (connected == peers_.size()) return true;
    }
    return false;
  }

  Result run() {
    Result result;
    result.clients = peers_.size();
    const std::uint64_t drops_before = total_drops();
    const proto::TimeUs tick_us = proto::kMicrosPerSecond / options_.rate_hz;
    const auto ticks = static_cast<std::uint64_t>(options_.seconds * options_.rate_hz);
    const std::vector<std::uint8_t> input(options_.input_bytes, 0x11);
    const std::vector<std::uint8_t> snapshot(options_.snapshot_bytes, 0x22);
    proto::TimeUs next_update = now_;
    for (std::size_t tick = 0; tick < ticks; ++tick) {
      now_ += tick_us;
      // The clients' inputs (not timed), then the server takes them as the game channel does.
      arriving_.clear();
      for (Peer& peer : peers_) {
        result.snapshots_taken += take_inbox(peer);
        peer.client->update(now_);
        peer.client->send_unreliable(input, now_);
        proto::Transmit transmit;
        while (peer.client->poll_transmit(transmit)) {
          arriving_.push_back({peer.address, std::move(transmit.bytes)});
        }
      }
      std::int64_t start = bench::thread_cpu_ns();
      for (const proto::Transmit& datagram : arriving_) {
        server_.receive(datagram.to, datagram.bytes, now_);  // `to` holds the sender here
      }
      proto::ServerEvent event;
      while (server_.poll_event(event)) {
        result.payloads_delivered += std::holds_alternative<proto::ServerUnreliable>(event);
      }
      result.receive_ns += cpu_ns_since(start);
      result.datagrams_in += arriving_.size();

      // Every client's snapshot.
      start = bench::thread_cpu_ns();
      for (std::size_t k = 0; k < peers_.size(); ++k)
        server_.send_unreliable(ids_[k], snapshot, now_);
      const std::size_t sent = poll_outgoing();
      result.send_ns += cpu_ns_since(start);
      result.datagrams_out += sent;
      deliver_outgoing();

      if (now_ >= next_update) {
        next_update = now_ + 10 * proto::kMicrosPerMilli;
        start = bench::thread_cpu_ns();
        server_.update(now_);
        poll_outgoing();
        result.update_ns += cpu_ns_since(start);
        ++result.updates;
        deliver_outgoing();
      }
      ++result.ticks;
    }
    result.drops = total_drops() - drops_before;
    return result;
  }

 private:
  static proto::GameServerConfig server_config(std::size_t clients) {
    proto::GameServerConfig config;
    config.protocol_id = proto::kProtocolId;
    config.token_key = token_key();
    config.max_clients = static_cast<int>(clients);
    config.max_half_open = static_cast<int>(clients);  // everyone connects in the same round
    return config;
  }

  std::uint64_t total_drops() const {
    std::uint64_t drops = 0;
    for (const std::uint64_t count : server_.counters().drops) drops += count;
    return drops;
  }

  /// Datagrams the server queued go to their clients' inboxes.
  /// Polls the server's datagrams into outgoing_'s slots, which keep their buffers from tick to
  /// tick as the game channel's DatagramSender does; returns how many came.
  std::size_t poll_outgoing() {
    const std::size_t before = outgoing_count_;
    for (;;) {
      if (outgoing_count_ == outgoing_.size()) outgoing_.emplace_back();
      if (!server_.poll_transmit(outgoing_[outgoing_count_])) break;
      ++outgoing_count_;
    }
    return outgoing_count_ - before;
  }

  /// Copies the polled datagrams into the peers' inboxes, as the kernel would.
  void deliver_outgoing() {
    for (std::size_t i = 0; i < outgoing_count_; ++i) {
      const proto::Transmit& transmit = outgoing_[i];
      if (const auto peer = peer_of_.find(transmit.to); peer != peer_of_.end()) {
        peers_[peer->second].inbox.push_back(transmit.bytes);
      }
    }
    outgoing_count_ = 0;
  }

  /// The peer's client takes its inbox; returns the payloads it received.
  std::uint64_t take_inbox(Peer& peer) {
    for (const auto& bytes : peer.inbox) peer.client->receive(kServerAddress, bytes, now_);
    peer.inbox.clear();
    std::uint64_t payloads = 0;
    proto::ClientEvent event;
    while (peer.client->poll_event(event)) {
      payloads += std::holds_alternative<proto::ClientUnreliable>(event);
    }
    return payloads;
  }

  /// Handshake traffic both ways until nothing is left to deliver.
  void exchange() {
    for (bool moved = true; moved;) {
      moved = false;
      proto::Transmit transmit;
      for (Peer& peer : peers_) {
        while (peer.client->poll_transmit(transmit)) {
          server_.receive(peer.address, transmit.bytes, now_);
          moved = true;
        }
      }
      if (poll_outgoing() > 0) moved = true;
      deliver_outgoing();
      for (Peer& peer : peers_) take_inbox(peer);
      proto::ServerEvent event;
      while (server_.poll_event(event)) {
        if (auto* connected = std::get_if<proto::ServerConnected>(&event)) {
          ids_[connected->account_id - kFirstAccount] = connected->client;
        }
      }
    }
  }

  BenchOptions options_;
  proto::GameServer server_;
  static constexpr std::uint64_t kFirstAccount = 1000;
  std::vector<Peer> peers_;
  std::vector<proto::ClientId> ids_;  ///< the server's id of each peer's connection
  std::unordered_map<proto::Address, std::size_t, proto::AddressHash> peer_of_;
  std::vector<proto::Transmit> outgoing_;
  std::size_t outgoing_count_ = 0;         ///< the slots of outgoing_ holding datagrams
  std::vector<proto::Transmit> arriving_;  ///< the clients' datagrams of a tick, by sender
  proto::TimeUs now_ = 1'000'000;
};

bench::JsonObject result(const Result& r, const BenchOptions& options) {
  const auto per = [](std::uint64_t ns, std::uint64_t count) {
    return count == 0 ? 0.0 : static_cast<double>(ns) / static_cast<double>(count);
  };
  return bench::result_line("transport")
      .integer("clients", r.clients)
      .integer("rate_hz", options.rate_hz)
      .integer("ticks", r.ticks)
      .integer("input_bytes", options.input_bytes)
      .integer("snapshot_bytes", options.snapshot_bytes)
      .number("ns_per_datagram_in", per(r.receive_ns, r.datagrams_in), 1)
      .number("ns_per_datagram_out", per(r.send_ns, r.datagrams_out), 1)
      .number("us_per_update", per(r.update_ns, r.updates) / 1000.0, 2)
      .integer("datagrams_in", r.datagrams_in)
      .integer("datagrams_out", r.datagrams_out)
      .integer("payloads_delivered", r.payloads_delivered)
      .integer("snapshots_taken", r.snapshots_taken)
      .integer("drops", r.drops);
}

}  // namespace

int main(int argc, char** argv) {
  BenchOptions options;
  std::vector<std::size_t> client_counts{64, 256, 1024};
  std::string out;
  CLI::App app{"transport-bench: the game channel's server end per datagram, in memory"};
  app.add_option("--clients", client_counts, "client counts, one line each")
      ->delimiter(',')
      ->check(CLI::Range(1, 4096));
  app.add_option("--seconds", options.seconds, "simulated seconds per count")
      ->check(CLI::Range(0.1, 600.0))
      ->capture_default_str();
  app.add_option("--rate", options.rate_hz, "ticks per second: one input and one snapshot each")
      ->check(CLI::Range(10, 128))
      ->capture_default_str();
  app.add_option("--input-bytes", options.input_bytes, "each client's unreliable payload, bytes")
      ->check(CLI::Range(1, 1100))
      ->capture_default_str();
  app.add_option("--snapshot-bytes", options.snapshot_bytes, "the server's payload, bytes")
      ->check(CLI::Range(1, 1100))
      ->capture_default_str();
  app.add_option("--out", out, "also append the JSON lines to this file");
  CLI11_PARSE(app, argc, argv);

  bench::ResultsOut results(out);
  if (!results.ok()) {
    std::fprintf(stderr, "transport-bench: cannot write %s\n", out.c_str());
    return 2;
  }
  for (const std::size_t clients : client_counts) {
    TransportBench bench(clients, options);
    if (!bench.connect()) {
      std::fprintf(stderr, "transport-bench: %zu clients did not all connect\n", clients);
      return 1;
    }
    results.write(result(bench.run(), options));
  }
  return 0;
}
