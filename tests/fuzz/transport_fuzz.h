#pragma once
/// What the transport fuzz targets and their seed writers share: the fixed keys and addresses,
/// and a server with one client that completed its handshake, so that fuzzed bodies can be
/// sealed under a real session key and reach the parsers behind the decryption.

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "ricochet/proto/connect_token.h"
#include "ricochet/proto/game_client.h"
#include "ricochet/proto/game_server.h"

namespace ricochet::proto::fuzz {

inline constexpr std::uint64_t kProtocolId = 0x52494330'0000F022ull;
inline constexpr TimeUs kNow = 1'000 * kMicrosPerSecond;
inline const Address kClientAddress = Address::ipv4(10, 1, 2, 3, 40000);
inline const Address kServerAddress = Address::ipv4(10, 9, 9, 9, 7778);

inline Key token_key() {
  Key key{};
  for (std::size_t i = 0; i < key.size(); ++i) key[i] = static_cast<std::uint8_t>(3 * i + 1);
  return key;
}

inline GameServerConfig server_config() {
  GameServerConfig config;
  config.protocol_id = kProtocolId;
  config.token_key = token_key();
  return config;
}

[[noreturn]] inline void fail(const char* what) {
  std::fprintf(stderr, "transport fuzz: %s\n", what);
  std::abort();
}

/// Writes seed files: the mode byte the targets read first, then the bytes.
struct SeedWriter {
  std::string dir;
  int written = 0;
  void save(const std::string& name, std::uint8_t mode, const std::vector<std::uint8_t>& bytes) {
    const std::string path = dir + "/" + name + ".bin";
    std::FILE* file = std::fopen(path.c_str(), "wb");
    if (!file) fail("cannot write a seed file");
    std::fputc(mode, file);
    std::fwrite(bytes.data(), 1, bytes.size(), file);
    std::fclose(file);
    ++written;
  }
};

/// A server and a client connected to it through direct delivery.
struct Session {
  std::unique_ptr<GameServer> server = std::make_unique<GameServer>(server_config());
  TokenGrant grant =
      issue_connect_token(token_key(), kProtocolId, 77, 5, kNow, 30 * kMicrosPerSecond, 5);
  std::unique_ptr<GameClient> client =
      std::make_unique<GameClient>(ClientConnectInfo{grant, kProtocolId, kServerAddress}, kNow);

  Session() {
    for (int round = 0; round < 4; ++round) pump();
    if (client->state() != ConnectionState::Connected) fail("the handshake did not complete");
  }
  /// Moves every queued datagram to the other end once.
  void pump() {
    Transmit transmit;
    while (client->poll_transmit(transmit)) server->receive(kClientAddress, transmit.bytes, kNow);
    while (server->poll_transmit(transmit)) client->receive(kServerAddress, transmit.bytes, kNow);
  }
  /// Drains events so that queues stay bounded.
  void drain() {
    ServerEvent server_event;
    while (server->poll_event(server_event)) {
    }
    ClientEvent client_event;
    while (client->poll_event(client_event)) {
    }
  }
};

}  // namespace ricochet::proto::fuzz
