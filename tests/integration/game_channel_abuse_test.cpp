// Attacks on the game channel's handshake and budgets, over real UDP sockets on 127.0.0.0/8 (all
// of it is loopback, so an attacker may send from many source addresses): each test plays the
// attack while a victim connects or plays, and asserts what the victim sees. The token-minting
// attack needs the control channel, so it runs against the whole Server; the others run one
// GameServer (the sans-IO server end) behind a socket that the test's thread pumps.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <iostream>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "control_test_client.h"
#include "game_test_client.h"
#include "ricochet/proto/connect_token.h"
#include "ricochet/proto/game_server.h"
#include "ricochet/proto/packet.h"
#include "server.h"
#include "temp_dir.h"

namespace ricochet::test::game_channel_abuse_test {
namespace {

using namespace std::chrono_literals;
using server::test::ControlTestClient;

/// A non-blocking UDP socket bound to `ip` (127.x.y.z) and a free port.
class UdpSocket {
 public:
  explicit UdpSocket(const char* ip = "127.0.0.1")
      : fd_(socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0)) {
    sockaddr_in address{};
    address.sin_family = AF_INET;
    inet_pton(AF_INET, ip, &address.sin_addr);
    if (fd_ < 0 || bind(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
      throw std::runtime_error(std::string("cannot bind a UDP socket on ") + ip);
    }
    socklen_t size = sizeof address;
    getsockname(fd_, reinterpret_cast<sockaddr*>(&address), &size);
    port_ = ntohs(address.sin_port);
  }
  ~UdpSocket() { close(fd_); }
  UdpSocket(const UdpSocket&) = delete;
  UdpSocket& operator=(const UdpSocket&) = delete;

  void send_to(std::uint16_t port, std::span<const std::uint8_t> bytes) const {
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    to.sin_port = htons(port);
    sendto(fd_, bytes.data(), bytes.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to);
  }
  int fd() const { return fd_; }
  std::uint16_t port() const { return port_; }

 private:
  int fd_;
  std::uint16_t port_ = 0;
};

/// One GameServer behind a socket on 127.0.0.1, pumped by the test's thread on the steady clock:
/// every waiting datagram in, update, every datagram out; events kept for the test.
class LoopbackGameServer {
 public:
  explicit LoopbackGameServer(proto::GameServerConfig config) : server_(std::move(config)) {
    const int buffer = 4 << 20;
    setsockopt(socket_.fd(), SOL_SOCKET, SO_RCVBUF, &buffer, sizeof buffer);
  }

  void pump() {
    const proto::TimeUs now = GameTestClient::now();
    std::array<std::uint8_t, 1500> buffer{};
    for (;;) {
      sockaddr_in from{};
      socklen_t size = sizeof from;
      const ssize_t got = recvfrom(socket_.fd(), buffer.data(), buffer.size(), 0,
                                   reinterpret_cast<sockaddr*>(&from), &size);
      if (got < 0) break;
      const std::uint32_t ip = ntohl(from.sin_addr.s_addr);
      server_.receive(proto::Address::ipv4(static_cast<std::uint8_t>(ip >> 24),
                                           static_cast<std::uint8_t>(ip >> 16),
                                           static_cast<std::uint8_t>(ip >> 8),
                                           static_cast<std::uint8_t>(ip), ntohs(from.sin_port)),
                      std::span(buffer.data(), static_cast<std::size_t>(got)), now);
    }
    server_.update(now);
    proto::Transmit transmit;
    while (server_.poll_transmit(transmit)) {
      sockaddr_in to{};
      to.sin_family = AF_INET;
      to.sin_addr.s_addr = htonl((std::uint32_t{transmit.to.ip[0]} << 24) |
                                 (std::uint32_t{transmit.to.ip[1]} << 16) |
                                 (std::uint32_t{transmit.to.ip[2]} << 8) | transmit.to.ip[3]);
      to.sin_port = htons(transmit.to.port);
      sendto(socket_.fd(), transmit.bytes.data(), transmit.bytes.size(), 0,
             reinterpret_cast<sockaddr*>(&to), sizeof to);
    }
    proto::ServerEvent event;
    while (server_.poll_event(event)) events_.push_back(std::move(event));
  }

  /// Payloads received from `account` so far.
  std::size_t payloads_from(std::uint64_t account) const {
    return static_cast<std::size_t>(
        std::count_if(events_.begin(), events_.end(), [account](const proto::ServerEvent& event) {
          const auto* payload = std::get_if<proto::ServerUnreliable>(&event);
          return payload && payload->account_id == account;
        }));
  }
  std::uint16_t port() const { return socket_.port(); }
  const proto::TransportCounters& counters() const { return server_.counters(); }

 private:
  UdpSocket socket_;
  proto::GameServer server_;
  std::vector<proto::ServerEvent> events_;
};

proto::GameServerConfig loopback_config(const proto::Key& token_key) {
  proto::GameServerConfig config;
  config.protocol_id = proto::kProtocolId;
  config.token_key = token_key;
  return config;
}

/// A join reply as the control channel would send it, for `account`'s token.
wire::JoinMatchReply join_reply(const proto::Key& token_key, std::uint64_t account) {
  const proto::TokenGrant grant =
      proto::issue_connect_token(token_key, proto::kProtocolId, account, 1, GameTestClient::now(),
                                 10 * proto::kMicrosPerSecond, 5);
  wire::JoinMatchReply join;
  join.set_connect_token(grant.connect_token.data(), grant.connect_token.size());
  join.set_client_to_server_key(grant.client_to_server.data(), grant.client_to_server.size());
  join.set_server_to_client_key(grant.server_to_client.data(), grant.server_to_client.size());
  join.set_timeout_s(grant.timeout_s);
  return join;
}

/// Pumps `victim` and `each_ms` until it is connected or `limit` passes; how long it took, or
/// nothing.
template <class Each>
std::optional<std::chrono::milliseconds> connect_within(GameTestClient& victim,
                                                        std::chrono::milliseconds limit,
                                                        Each each_ms) {
  const auto start = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - start < limit) {
    victim.pump_for(5ms, each_ms);
    if (victim.transport().state() == proto::ConnectionState::Connected) {
      return std::chrono::duration_cast<std::chrono::milliseconds>(
          std::chrono::steady_clock::now() - start);
    }
  }
  return std::nullopt;
}

TEST(GameChannelAbuse, AFloodOfOneByteDatagramsFromManyAddressesDoesNotStopAVictimConnecting) {
  const proto::Key key = proto::random_key();
  proto::GameServerConfig config = loopback_config(key);
  config.max_tracked_addresses = 256;  // a flood of 300 addresses fills it (4096 by default)
  LoopbackGameServer server(config);
  // 300 sources on 127.0.0.2..4, each sending a byte every 25 ms: 12,000 datagrams a second.
  std::vector<std::unique_ptr<UdpSocket>> sources;
  for (int i = 0; i < 300; ++i) {
    sources.push_back(
        std::make_unique<UdpSocket>(("127.0.0." + std::to_string(2 + i / 100)).c_str()));
  }
  const std::array<std::uint8_t, 1> byte{0x42};
  auto next = std::chrono::steady_clock::now();
  const auto flood = [&] {
    server.pump();
    if (std::chrono::steady_clock::now() < next) return;
    next += 25ms;
    for (const auto& source : sources) source->send_to(server.port(), byte);
  };
  const auto warm_up = std::chrono::steady_clock::now() + 300ms;
  while (std::chrono::steady_clock::now() < warm_up) {
    flood();
    std::this_thread::sleep_for(1ms);
  }

  GameTestClient victim(join_reply(key, 1), server.port());
  const auto took = connect_within(victim, 2s, flood);
  EXPECT_TRUE(took) << "the victim did not connect within 2 s; "
                    << server.counters().dropped(proto::DropReason::AddressTableFull)
                    << " datagrams dropped for a full address table";
  if (took) std::cout << "victim connected in " << took->count() << " ms under the flood\n";
  EXPECT_EQ(server.counters().dropped(proto::DropReason::AddressTableFull), 0u)
      << "a datagram that cannot be a connection request takes no table entry";
  std::cout << server.counters().dropped(proto::DropReason::Malformed)
            << " flood datagrams dropped as malformed (0x42 is no packet type)\n";
  EXPECT_GT(server.counters().dropped(proto::DropReason::Malformed), 1'000u)
      << "the flood came (300 datagrams every 25 ms for 300 ms and more) and was counted";
}

TEST(GameChannelAbuse, ASpoofedRequestDoesNotReplaceAVictimsHandshake) {
  const proto::Key key = proto::random_key();
  LoopbackGameServer server(loopback_config(key));
  const wire::JoinMatchReply attacker = join_reply(key, 2);
  const std::vector<std::uint8_t> spoofed = proto::write_connection_request(
      proto::kProtocolId,
      std::span(reinterpret_cast<const std::uint8_t*>(attacker.connect_token().data()),
                attacker.connect_token().size()));
  GameTestClient victim(join_reply(key, 1), server.port());
  // The attacker's valid request with the victim's source address, every millisecond: between
  // the victim's request and its response.
  const auto took = connect_within(victim, 2s, [&] {
    server.pump();
    victim.send_raw(spoofed);
  });
  EXPECT_TRUE(took) << "the victim did not connect within 2 s";
  if (took) std::cout << "victim connected in " << took->count() << " ms under spoofed requests\n";
  EXPECT_GT(server.counters().dropped(proto::DropReason::HandshakeInProgress), 0u);
}

TEST(GameChannelAbuse, SpoofedPacketsWithAClientsAddressDoNotSpendItsBudget) {
  const proto::Key key = proto::random_key();
  LoopbackGameServer server(loopback_config(key));
  GameTestClient victim(join_reply(key, 1), server.port());
  ASSERT_TRUE(connect_within(victim, 2s, [&] { server.pump(); }));
  // Payload-shaped datagrams nobody can authenticate, five a millisecond, with the victim's
  // address, while the victim sends 60 payloads a second for 2 s.
  std::vector<std::uint8_t> forged(64, 0xA5);
  forged[0] = static_cast<std::uint8_t>(proto::PacketType::Payload);
  std::uint64_t sent = 0;
  std::uint64_t forged_sent = 0;
  const std::size_t before = server.payloads_from(1);
  auto next_input = std::chrono::steady_clock::now();
  victim.pump_for(2s, [&] {
    for (int i = 0; i < 5; ++i, ++forged_sent) {
      forged[1] = static_cast<std::uint8_t>(forged_sent);  // a fresh sequence each
      forged[2] = static_cast<std::uint8_t>(forged_sent >> 8);
      victim.send_raw(forged);
    }
    server.pump();
    if (std::chrono::steady_clock::now() >= next_input) {
      next_input += std::chrono::microseconds(16'667);
      victim.send("input");
      ++sent;
    }
  });
  for (int i = 0; i < 20; ++i) {  // what is still on its way
    server.pump();
    std::this_thread::sleep_for(1ms);
  }
  const std::size_t arrived = server.payloads_from(1) - before;
  std::cout << arrived << " of " << sent << " victim payloads arrived beside " << forged_sent
            << " forged datagrams\n";
  EXPECT_GE(arrived * 100, sent * 95) << "the victim keeps >= 95 % of its payloads";
  EXPECT_EQ(victim.transport().state(), proto::ConnectionState::Connected);
  EXPECT_GT(server.counters().dropped(proto::DropReason::ForgedMac), forged_sent / 2);
}

TEST(GameChannelAbuse, ManyTokensOfOneAccountFromManySocketsDoNotFillTheHandshakeSlots) {
  const proto::Key key = proto::random_key();
  proto::GameServerConfig config = loopback_config(key);
  config.max_half_open = 64;
  LoopbackGameServer server(config);
  // Mallory's tokens as JoinMatch hands them out, 60 a second, each sent from its own socket
  // every 50 ms: the transport's part of the minting attack (the control channel's part, one
  // new token a second per account, is the test below).
  struct Pending {
    std::unique_ptr<UdpSocket> socket;
    std::vector<std::uint8_t> request;
  };
  std::vector<Pending> pending;
  auto next_token = std::chrono::steady_clock::now();
  auto next_send = next_token;
  const auto attack = [&] {
    server.pump();
    const auto now = std::chrono::steady_clock::now();
    if (now >= next_token) {
      next_token += std::chrono::microseconds(1'000'000 / 60);
      const wire::JoinMatchReply join = join_reply(key, 66);
      pending.push_back({std::make_unique<UdpSocket>(),
                         proto::write_connection_request(
                             proto::kProtocolId, std::span(reinterpret_cast<const std::uint8_t*>(
                                                               join.connect_token().data()),
                                                           join.connect_token().size()))});
    }
    if (now >= next_send) {
      next_send += 50ms;
      for (const Pending& one : pending) one.socket->send_to(server.port(), one.request);
    }
  };
  const auto warm_up = std::chrono::steady_clock::now() + 2s;
  while (std::chrono::steady_clock::now() < warm_up) {
    attack();
    std::this_thread::sleep_for(1ms);
  }
  GameTestClient victim(join_reply(key, 1), server.port());
  const auto took = connect_within(victim, 2s, attack);
  std::cout << pending.size() << " tokens of one account from as many sockets; the victim "
            << (took ? "connected in " + std::to_string(took->count()) + " ms"
                     : std::string("did not connect within 2 s"))
            << "; half-open now " << server.counters().half_open << "\n";
  EXPECT_TRUE(took);
  EXPECT_LE(server.counters().half_open, 1u) << "the account holds one handshake at most";
}

/// Signs `name` in on a fresh control connection (registering it when `fresh`).
std::unique_ptr<ControlTestClient> session(std::uint16_t port, const std::string& name,
                                           bool fresh) {
  auto client = std::make_unique<ControlTestClient>(port);
  EXPECT_TRUE(client->connect());
  client->sign_in(name, fresh);
  return client;
}

TEST(GameChannelAbuse, OneAccountMintingTokensFromThreeSessionsDoesNotBlockAVictimsJoin) {
  TempDir dir("ricochet-abuse");
  server::ServerConfig config;
  config.server.data_dir = (dir.path() / "data").string();
  config.server.threads = 2;
  config.server.shutdown_grace_s = 5;
  config.db.password_hashing = server::PasswordHashing::Minimum;
  config.control.bind = "127.0.0.1";
  config.control.port = 0;
  config.game.bind = "127.0.0.1";
  config.game.port = 0;
  config.game.max_half_open = 64;  // filled in about a second at 60 tokens a second
  config.admin.port = 0;
  config.matches.count = 1;
  config.matches.maps = {RICOCHET_SOURCE_DIR "/server/maps/arena.toml"};
  server::Server server(config);
  server.start();

  // Mallory: three sessions of one account, each asking to join as fast as its control budget
  // lets it (20 a second), and every token sent from its own socket every 50 ms.
  std::vector<std::unique_ptr<ControlTestClient>> mallory;
  for (int i = 0; i < 3; ++i) mallory.push_back(session(server.control_port(), "mallory", i == 0));
  struct Pending {
    std::unique_ptr<UdpSocket> socket;
    std::vector<std::uint8_t> request;
  };
  std::vector<Pending> pending;
  auto next_join = std::chrono::steady_clock::now();
  auto next_send = next_join;
  std::size_t joins = 0;
  const auto attack = [&] {
    const auto now = std::chrono::steady_clock::now();
    if (now >= next_join) {
      next_join += std::chrono::microseconds(1'000'000 / 60);
      const wire::ServerMessage reply =
          mallory[joins++ % mallory.size()]->request(ControlTestClient::join(1));
      if (reply.has_join_match()) {
        const std::string& token = reply.join_match().connect_token();
        pending.push_back(
            {std::make_unique<UdpSocket>(),
             proto::write_connection_request(
                 proto::kProtocolId,
                 std::span(reinterpret_cast<const std::uint8_t*>(token.data()), token.size()))});
      }
    }
    if (now >= next_send) {
      next_send += 50ms;
      for (const Pending& one : pending) one.socket->send_to(server.game_port(), one.request);
    }
  };
  auto victim_control = session(server.control_port(), "victim", true);
  const auto warm_up = std::chrono::steady_clock::now() + 2s;
  while (std::chrono::steady_clock::now() < warm_up) {
    attack();
    std::this_thread::sleep_for(1ms);
  }

  const wire::ServerMessage reply = victim_control->request(ControlTestClient::join(1));
  ASSERT_TRUE(reply.has_join_match()) << reply.DebugString();
  GameTestClient victim(reply.join_match(), server.game_port());
  const auto took = connect_within(victim, 2s, attack);
  std::cout << "mallory asked " << joins << " times and sent " << pending.size()
            << " tokens from as many sockets; the victim "
            << (took ? "connected in " + std::to_string(took->count()) + " ms"
                     : std::string("did not connect within 2 s"))
            << "\n";
  EXPECT_TRUE(took);
  EXPECT_GT(joins, 100u) << "the attack ran at its rate";
}

}  // namespace
}  // namespace ricochet::test::game_channel_abuse_test
