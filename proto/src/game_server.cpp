#include "ricochet/proto/game_server.h"

#include <algorithm>
#include <boost/unordered/unordered_flat_map.hpp>
#include <cstring>
#include <optional>
#include <stdexcept>

#include "byte_io.h"
#include "connection.h"
#include "ricochet/proto/connect_token.h"
#include "ricochet/proto/crypto.h"
#include "ricochet/proto/packet.h"
#include "ricochet/proto/token_bucket.h"
#include "ricochet/proto/transport_states.h"
#include "transmit_queue.h"

namespace ricochet::proto {
namespace {

struct TokenMacHash {
  std::size_t operator()(const TokenMac& mac) const noexcept {
    std::uint64_t value;
    std::memcpy(&value, mac.data(), sizeof value);  // a MAC is uniformly random already
    return static_cast<std::size_t>(value);
  }
};

/// A handshake in progress (state Challenged): the token's contents and the session that the
/// response is decrypted with and that becomes the connection.
struct Handshake {
  ConnectTokenContents token;
  TokenMac mac{};
  TimeUs expires_at = 0;
  ChallengeBody challenge;
  Connection connection;
};

struct Client {
  ClientId id = 0;
  Address address;
  std::uint64_t account_id = 0;
  std::uint32_t match_id = 0;
  Connection connection;
  TokenBucket budget;
};

/// Why a datagram from an address the server holds nothing for (no connection, handshake or
/// budget) cannot start a connection, or nothing when it can. Only a request of the exact size
/// with this version, as netcode.io checks, makes the server spend memory on an address.
std::optional<DropReason> not_a_request(std::span<const std::uint8_t> datagram) {
  if (datagram[0] != static_cast<std::uint8_t>(PacketType::ConnectionRequest)) {
    auto header = read_encrypted_header(datagram);
    return header.ok() ? DropReason::UnknownAddress : *header.error;
  }
  if (datagram.size() != kConnectionRequestBytes) return DropReason::Truncated;  // never larger
  if (!std::equal(kVersionInfo.begin(), kVersionInfo.end(), datagram.begin() + 1)) {
    return DropReason::WrongVersion;
  }
  return std::nullopt;
}

std::vector<std::uint8_t> challenge_plaintext(const Handshake& handshake, const Address& to) {
  std::vector<std::uint8_t> plain;
  ByteWriter writer(plain);
  writer.u64(handshake.token.account_id);
  writer.u32(handshake.token.match_id);
  writer.bytes(handshake.mac);
  writer.bytes(to.ip);
  writer.u16(to.port);
  writer.u8(to.v6 ? 1 : 0);
  return plain;
}

}  // namespace

std::string GameServerConfig::validate() const {
  auto range = [](const char* field, double value, double min, double max) -> std::string {
    if (value >= min && value <= max) return {};
    return std::string(field) + " must be " + std::to_string(min) + ".." + std::to_string(max) +
           ", got " + std::to_string(value);
  };
  for (const std::string& problem :
       {range("max_clients", max_clients, 1, 4096), range("max_half_open", max_half_open, 1, 65536),
        range("max_tracked_addresses", max_tracked_addresses, 1, 1 << 20),
        range("max_half_open_per_host", max_half_open_per_host, 1, 65536),
        range("max_clients_per_host", max_clients_per_host, 1, 4096),
        range("max_used_tokens", max_used_tokens, 1, 1 << 24),
        range("address_packets_per_s", address_packets_per_s, 1, 1e6),
        range("address_burst", address_burst, 1, 1e6),
        range("client_packets_per_s", client_packets_per_s, 1, 1e6),
        range("client_burst", client_burst, 1, 1e6),
        range("keep_alive_us", static_cast<double>(keep_alive_us), 1000, 1e6),
        range("reliable_resend_us", static_cast<double>(reliable_resend_us), 1000, 5e6),
        range("max_reliable_pending", static_cast<double>(max_reliable_pending), 1, 256),
        range("max_reliable_queued", static_cast<double>(max_reliable_queued),
              static_cast<double>(max_reliable_pending), 65536)}) {
    if (!problem.empty()) return problem;
  }
  return {};
}

/// How often update() forgets expired used tokens and refilled address budgets, µs: each sweep
/// visits every entry, and a thousand clients' tokens are alive for their whole lifetime.
constexpr TimeUs kSweepIntervalUs = 100 * kMicrosPerMilli;

struct GameServer::State {
  GameServerConfig config;
  Key challenge_key = random_key();
  std::uint64_t challenge_sequence = 0;
  std::uint64_t handshake_sequence = 0;
  ClientId next_client = 1;
  using Handshakes = std::unordered_map<Address, Handshake, AddressHash>;
  Handshakes handshakes;
  /// Where each account's handshake in progress is: an account has at most one.
  boost::unordered_flat_map<std::uint64_t, Address> handshake_by_account;
  using HostCounts = boost::unordered_flat_map<HostKey, int, HostKeyHash>;
  HostCounts half_open_by_host;  ///< handshakes in progress per host; no zero entries
  HostCounts clients_by_host;    ///< connected clients per host; no zero entries
  // Open addressing for what a datagram looks up: a probe of a flat array of keys instead of
  // a bucket and a node in two cold places.
  boost::unordered_flat_map<ClientId, std::unique_ptr<Client>> clients;  ///< Clients never move
  /// The clients of `clients` by address: a datagram finds its client with one lookup.
  boost::unordered_flat_map<Address, Client*, AddressHash> client_by_address;
  boost::unordered_flat_map<std::uint64_t, ClientId> client_by_account;
  /// Every token that opened a handshake, with its expiry: a token opens one handshake only
  /// (another would reuse its keys and nonces). Forgotten once expired, when it opens nothing.
  boost::unordered_flat_map<TokenMac, TimeUs, TokenMacHash> used_tokens;
  boost::unordered_flat_map<Address, TokenBucket, AddressHash> address_budgets;
  TransmitQueue transmits;
  std::deque<ServerEvent> events;
  TransportCounters counters;
  std::uint64_t resends_of_gone_clients = 0;  ///< keeps counters.reliable_resends monotonic
  TimeUs next_sweep = 0;                      ///< of used tokens and address budgets, by update()

  void drop(DropReason reason, const Address& from) {
    ++counters.drops[static_cast<std::size_t>(reason)];
    if (config.log.on_drop) config.log.on_drop(reason, from);
  }
  void transition(const Address& address, ClientId client, ConnectionState from, ConnectionState to,
                  std::string_view reason) {
    if (config.log.on_transition) config.log.on_transition({address, client, from, to, reason});
  }
  void send(const Address& to, std::vector<std::uint8_t> bytes) {
    count_sent(bytes.size());
    transmits.push(to, std::move(bytes));
  }
  void send_payload(Client& client, std::span<const std::uint8_t> unreliable, TimeUs now) {
    std::vector<std::uint8_t>& packet = transmits.push(client.address);
    client.connection.make_payload(unreliable, now, packet);
    count_sent(packet.size());
  }
  void count_sent(std::size_t bytes) {
    ++counters.packets_out;
    counters.bytes_out += bytes;
  }
  void update_gauges() {
    counters.half_open = static_cast<std::uint32_t>(handshakes.size());
    counters.connected = static_cast<std::uint32_t>(clients.size());
  }
  ConnectionTiming timing(std::uint32_t timeout_s) const {
    return {static_cast<TimeUs>(timeout_s) * kMicrosPerSecond, config.keep_alive_us,
            config.reliable_resend_us, config.max_reliable_pending, config.max_reliable_queued};
  }

  /// Rate limit of an unconnected address, before any parsing.
  bool within_address_budget(const Address& from, TimeUs now) {
    auto it = address_budgets.find(from);
    if (it == address_budgets.end()) {
      if (address_budgets.size() >= static_cast<std::size_t>(config.max_tracked_addresses)) {
        drop(DropReason::AddressTableFull, from);
        return false;
      }
      it = address_budgets
               .emplace(from, TokenBucket(config.address_packets_per_s, config.address_burst, now))
               .first;
    }
    if (it->second.take(now)) return true;
    drop(DropReason::AddressRateLimited, from);
    return false;
  }

  ConnectionState state_of(const Address& address) const {
    if (client_by_address.contains(address)) return ConnectionState::Connected;
    if (handshakes.contains(address)) return ConnectionState::Challenged;
    return ConnectionState::Connecting;
  }

  /// Tells the token holder why it is refused (only it can read the packet), and counts it.
  void deny(const Address& to, const ConnectTokenContents& token, DisconnectReason reason) {
    send(to, seal_packet(PacketType::ConnectionDenied, kHandshakeSequenceBit | handshake_sequence++,
                         config.protocol_id, token.server_to_client, write_denied_body(reason)));
    drop(reason == DisconnectReason::HostFull ? DropReason::HostFull : DropReason::ServerFull, to);
  }

  void send_challenge(const Address& to, const Handshake& handshake) {
    send(to, seal_packet(PacketType::Challenge, kHandshakeSequenceBit | handshake_sequence++,
                         config.protocol_id, handshake.token.server_to_client,
                         write_challenge_body(handshake.challenge)));
  }

  static void count_on(HostCounts& counts, const Address& address, int delta) {
    auto it = counts.try_emplace(host_key(address), 0).first;
    it->second += delta;
    if (it->second <= 0) counts.erase(it);
  }
  static int count_of(const HostCounts& counts, const HostKey& host) {
    auto it = counts.find(host);
    return it == counts.end() ? 0 : it->second;
  }

  bool full() const { return clients.size() >= static_cast<std::size_t>(config.max_clients); }
  /// Why `account_id` may not connect from `from` now (Denied: server full, or HostFull), or
  /// nothing. A returning account replaces its old connection, so it never counts as one more
  /// client, on the server or on its old connection's host.
  std::optional<DisconnectReason> refusal(std::uint64_t account_id, const Address& from) const {
    const Client* old = nullptr;
    if (auto it = client_by_account.find(account_id); it != client_by_account.end()) {
      old = clients.find(it->second)->second.get();
    }
    if (!old && full()) return DisconnectReason::Denied;
    const HostKey host = host_key(from);
    int on_host = count_of(clients_by_host, host);
    if (old && host_key(old->address) == host) --on_host;
    if (on_host >= config.max_clients_per_host) return DisconnectReason::HostFull;
    return std::nullopt;
  }

  void open_handshake(const Address& from, Handshake handshake) {
    handshake_by_account[handshake.token.account_id] = from;
    count_on(half_open_by_host, from, +1);
    handshakes.emplace(from, std::move(handshake));
  }
  /// Forgets the handshake at `it` (connected, timed out, replaced or denied) in every table.
  Handshakes::iterator close_handshake(Handshakes::iterator it) {
    if (auto account = handshake_by_account.find(it->second.token.account_id);
        account != handshake_by_account.end() && account->second == it->first) {
      handshake_by_account.erase(account);
    }
    count_on(half_open_by_host, it->first, -1);
    return handshakes.erase(it);
  }

  void on_request(const Address& from, std::span<const std::uint8_t> datagram, TimeUs now);
  void on_client_datagram(Client& client, std::span<const std::uint8_t> datagram, TimeUs now);
  void on_handshake_packet(const Address& from, const EncryptedHeader& header,
                           std::span<const std::uint8_t> datagram, TimeUs now);
  void on_client_packet(Client& client, const EncryptedHeader& header,
                        std::span<const std::uint8_t> datagram, TimeUs now);
  void complete_handshake(const Address& from, Handshake& handshake, TimeUs now);
  void remove_client(ClientId id, DisconnectReason reason, bool tell_client, TimeUs now);
};

void GameServer::State::on_request(const Address& from, std::span<const std::uint8_t> datagram,
                                   TimeUs now) {
  auto request = read_connection_request(datagram);
  if (!request.ok()) return drop(*request.error, from);
  if (request.value.protocol_id != config.protocol_id) return drop(DropReason::WrongProtocol, from);
  if (!server_accepts(state_of(from), PacketType::ConnectionRequest)) {
    return drop(DropReason::WrongState, from);
  }
  auto token =
      open_connect_token(config.token_key, config.protocol_id, request.value.connect_token, now);
  if (!token.ok()) return drop(*token.error, from);
  const TokenMac& mac = token.value.mac;
  const ConnectTokenContents& contents = token.value.contents;
  auto existing = handshakes.find(from);
  if (used_tokens.contains(mac)) {
    // A token opens one handshake. The same request again gets its challenge again (the first
    // was lost); anything else is a copy from elsewhere, or a retry that would reuse the token's
    // keys, and with them the nonces, of a handshake that ended.
    if (existing != handshakes.end() && existing->second.mac == mac) {
      return send_challenge(from, existing->second);
    }
    return drop(DropReason::TokenReused, from);
  }
  // Another account's token never ends a handshake in progress: its source may be spoofed.
  if (existing != handshakes.end() && existing->second.token.account_id != contents.account_id) {
    return drop(DropReason::HandshakeInProgress, from);
  }
  // A newer token of the account replaces the account's handshake in progress, from this
  // address or another: one account holds one half-open slot at most.
  auto replaced = existing;
  if (replaced == handshakes.end()) {
    if (auto pending = handshake_by_account.find(contents.account_id);
        pending != handshake_by_account.end()) {
      replaced = handshakes.find(pending->second);
    }
  }
  const bool replaces = replaced != handshakes.end();
  if (!replaces && handshakes.size() >= static_cast<std::size_t>(config.max_half_open)) {
    return drop(DropReason::HalfOpenCap, from);
  }
  const HostKey host = host_key(from);
  const int on_host =
      count_of(half_open_by_host, host) - (replaces && host_key(replaced->first) == host ? 1 : 0);
  if (on_host >= config.max_half_open_per_host) return drop(DropReason::HostHalfOpenCap, from);
  if (used_tokens.size() >= static_cast<std::size_t>(config.max_used_tokens)) {
    return drop(DropReason::UsedTokenTableFull, from);
  }
  if (auto refused = refusal(contents.account_id, from)) return deny(from, contents, *refused);
  if (replaces) {
    transition(replaced->first, 0, ConnectionState::Challenged, ConnectionState::Disconnected,
               "replaced by a newer token of its account");
    close_handshake(replaced);
  }
  used_tokens[mac] = contents.expires_at;
  Handshake handshake{contents,
                      mac,
                      now + static_cast<TimeUs>(contents.timeout_s) * kMicrosPerSecond,
                      {},
                      Connection(config.protocol_id, contents.server_to_client,
                                 contents.client_to_server, timing(contents.timeout_s), now)};
  handshake.challenge.challenge_sequence = challenge_sequence++;
  std::vector<std::uint8_t> sealed;
  seal_chacha(challenge_plaintext(handshake, from), kVersionInfo,
              handshake.challenge.challenge_sequence, challenge_key, sealed);
  std::memcpy(handshake.challenge.challenge_token.data(), sealed.data(), kChallengeTokenBytes);
  transition(from, 0, ConnectionState::Connecting, ConnectionState::Challenged,
             "valid connection request");
  send_challenge(from, handshake);
  open_handshake(from, std::move(handshake));
  update_gauges();
}

void GameServer::State::on_handshake_packet(const Address& from, const EncryptedHeader& header,
                                            std::span<const std::uint8_t> datagram, TimeUs now) {
  const auto found = handshakes.find(from);
  Handshake& handshake = found->second;
  if (!server_accepts(ConnectionState::Challenged, header.type)) {
    return drop(DropReason::WrongState, from);
  }
  std::vector<std::uint8_t> body;
  if (auto error = handshake.connection.open(header, datagram, body, now)) {
    return drop(*error, from);
  }
  auto response = read_challenge_body(body);
  if (!response.ok()) return drop(*response.error, from);
  // The challenge must open under the challenge key, name this token and address, and be this
  // handshake's own (an older handshake's challenge, replayed, has another sequence).
  std::vector<std::uint8_t> plain;
  if (response.value.challenge_sequence != handshake.challenge.challenge_sequence ||
      !open_chacha(response.value.challenge_token, kVersionInfo, response.value.challenge_sequence,
                   challenge_key, plain) ||
      plain != challenge_plaintext(handshake, from)) {
    return drop(DropReason::ChallengeInvalid, from);
  }
  if (auto refused = refusal(handshake.token.account_id, from)) {
    deny(from, handshake.token, *refused);
    transition(from, 0, ConnectionState::Challenged, ConnectionState::Disconnected,
               "server or host full at response");
    close_handshake(found);
    update_gauges();
    return;
  }
  complete_handshake(from, handshake, now);
}

void GameServer::State::complete_handshake(const Address& from, Handshake& handshake, TimeUs now) {
  const std::uint64_t account_id = handshake.token.account_id;
  if (auto old = client_by_account.find(account_id); old != client_by_account.end()) {
    remove_client(old->second, DisconnectReason::Replaced, true, now);
  }
  const ClientId id = next_client++;
  Client client{id,
                from,
                account_id,
                handshake.token.match_id,
                std::move(handshake.connection),
                TokenBucket(config.client_packets_per_s, config.client_burst, now)};
  close_handshake(handshakes.find(from));
  address_budgets.erase(from);
  count_on(clients_by_host, from, +1);
  transition(from, id, ConnectionState::Challenged, ConnectionState::Connected,
             "valid challenge response");
  ++counters.connections_total;
  events.push_back(ServerConnected{id, account_id, client.match_id, from});
  send(from, client.connection.make_keep_alive(now));
  client_by_account[account_id] = id;
  client_by_address[from] =
      clients.emplace(id, std::make_unique<Client>(std::move(client))).first->second.get();
  update_gauges();
}

void GameServer::State::on_client_packet(Client& client, const EncryptedHeader& header,
                                         std::span<const std::uint8_t> datagram, TimeUs now) {
  if (!server_accepts(ConnectionState::Connected, header.type)) {
    return drop(DropReason::WrongState, client.address);
  }
  std::vector<std::uint8_t> body;
  if (auto error = client.connection.open(header, datagram, body, now)) {
    return drop(*error, client.address);
  }
  client.budget.take(now);  // authenticated: the client's own packet
  switch (header.type) {
    case PacketType::Response: {
      // Our keep-alive after the handshake was lost; the client still waits for one.
      if (auto response = read_challenge_body(body); !response.ok()) {
        return drop(*response.error, client.address);
      }
      send(client.address, client.connection.make_keep_alive(now));
      return;
    }
    case PacketType::KeepAlive: {
      auto ack = read_keep_alive_body(body);
      if (!ack.ok()) return drop(*ack.error, client.address);
      client.connection.on_ack(ack.value, now);
      return;
    }
    case PacketType::Payload: {
      auto payload = read_payload_body(std::move(body));
      if (!payload.ok()) return drop(*payload.error, client.address);
      client.connection.on_ack(payload.value.ack, now);
      if (!client.connection.on_reliable(payload.value.reliable)) {
        drop(DropReason::ReliableOutOfWindow, client.address);
      }
      std::vector<std::uint8_t> message;
      while (client.connection.pop_reliable(message)) {
        events.push_back(ServerReliable{client.id, std::move(message)});
      }
      if (!payload.value.unreliable.empty()) {
        events.push_back(ServerUnreliable{client.id, std::move(payload.value.unreliable),
                                          client.account_id, client.connection.rtt_us()});
      }
      return;
    }
    case PacketType::Disconnect: {
      auto disconnect = read_disconnect_body(body);
      if (!disconnect.ok()) return drop(*disconnect.error, client.address);
      remove_client(client.id, DisconnectReason::PeerRequested, false, now);
      return;
    }
    default:
      return drop(DropReason::WrongState, client.address);
  }
}

void GameServer::State::on_client_datagram(Client& client, std::span<const std::uint8_t> datagram,
                                           TimeUs now) {
  // Only packets that authenticate spend the budget (on_client_packet), so packets spoofed
  // with the client's address cannot use it up: an empty budget is the client's own doing.
  if (!client.budget.available(now)) return drop(DropReason::ClientRateLimited, client.address);
  if (datagram[0] == static_cast<std::uint8_t>(PacketType::ConnectionRequest)) {
    return drop(DropReason::WrongState, client.address);
  }
  auto header = read_encrypted_header(datagram);
  if (!header.ok()) return drop(*header.error, client.address);
  on_client_packet(client, header.value, datagram, now);
}

void GameServer::State::remove_client(ClientId id, DisconnectReason reason, bool tell_client,
                                      TimeUs now) {
  auto it = clients.find(id);
  if (it == clients.end()) return;
  Client& client = *it->second;
  if (tell_client) {
    for (int copy = 0; copy < kDisconnectCopies; ++copy) {
      send(client.address, client.connection.make_disconnect(reason, now));
    }
  }
  ++counters.disconnects[static_cast<std::size_t>(reason)];
  resends_of_gone_clients += client.connection.reliable_resends();
  transition(client.address, id, ConnectionState::Connected, ConnectionState::Disconnected,
             name(reason));
  events.push_back(ServerDisconnected{id, client.account_id, reason});
  client_by_address.erase(client.address);
  count_on(clients_by_host, client.address, -1);
  if (auto account = client_by_account.find(client.account_id);
      account != client_by_account.end() && account->second == id) {
    client_by_account.erase(account);
  }
  clients.erase(it);
  update_gauges();
}

GameServer::GameServer(GameServerConfig config) : state_(std::make_unique<State>()) {
  if (std::string problem = config.validate(); !problem.empty()) {
    throw std::invalid_argument("GameServerConfig: " + problem);
  }
  state_->config = std::move(config);
}

GameServer::~GameServer() = default;

void GameServer::receive(const Address& from, std::span<const std::uint8_t> datagram, TimeUs now) {
  State& s = *state_;
  ++s.counters.packets_in;
  s.counters.bytes_in += datagram.size();
  if (datagram.empty()) return s.drop(DropReason::Empty, from);
  if (datagram.size() > kMaxDatagramBytes) return s.drop(DropReason::Oversized, from);
  if (auto client = s.client_by_address.find(from); client != s.client_by_address.end()) {
    return s.on_client_datagram(*client->second, datagram, now);
  }
  const bool challenged = s.handshakes.contains(from);
  if (!challenged && !s.address_budgets.contains(from)) {
    if (auto reason = not_a_request(datagram)) return s.drop(*reason, from);
  }
  if (!s.within_address_budget(from, now)) return;
  if (datagram[0] == static_cast<std::uint8_t>(PacketType::ConnectionRequest)) {
    return s.on_request(from, datagram, now);
  }
  auto header = read_encrypted_header(datagram);
  if (!header.ok()) return s.drop(*header.error, from);
  if (challenged) return s.on_handshake_packet(from, header.value, datagram, now);
  s.drop(DropReason::UnknownAddress, from);
}

void GameServer::update(TimeUs now) {
  State& s = *state_;
  for (auto it = s.handshakes.begin(); it != s.handshakes.end();) {
    if (now >= it->second.expires_at) {
      s.transition(it->first, 0, ConnectionState::Challenged, ConnectionState::Disconnected,
                   "handshake timed out");
      it = s.close_handshake(it);
    } else {
      ++it;
    }
  }
  std::vector<ClientId> silent;
  s.counters.reliable_resends = s.resends_of_gone_clients;
  for (auto& [id, client_ptr] : s.clients) {
    Client& client = *client_ptr;
    s.counters.reliable_resends += client.connection.reliable_resends();
    if (client.connection.timed_out(now)) {
      silent.push_back(id);
    } else if (client.connection.reliable_due(now)) {
      s.send_payload(client, {}, now);
    } else if (client.connection.keep_alive_due(now)) {
      s.send(client.address, client.connection.make_keep_alive(now));
    }
  }
  for (ClientId id : silent) s.remove_client(id, DisconnectReason::TimedOut, false, now);
  if (now >= s.next_sweep) {
    // Memory only: an expired token is refused before this table is read, and a full budget is
    // a fresh one.
    s.next_sweep = now + kSweepIntervalUs;
    boost::unordered::erase_if(s.used_tokens,
                               [&](const auto& entry) { return entry.second <= now; });
    boost::unordered::erase_if(s.address_budgets,
                               [&](auto& entry) { return entry.second.full(now); });
  }
  s.update_gauges();
}

bool GameServer::poll_transmit(Transmit& out) {
  return state_->transmits.pop(out);
}

bool GameServer::poll_event(ServerEvent& out) {
  if (state_->events.empty()) return false;
  out = std::move(state_->events.front());
  state_->events.pop_front();
  return true;
}

bool GameServer::send_unreliable(ClientId id, std::span<const std::uint8_t> payload, TimeUs now) {
  auto it = state_->clients.find(id);
  if (it == state_->clients.end() || payload.size() > kMaxUnreliableBytes) return false;
  state_->send_payload(*it->second, payload, now);
  return true;
}

bool GameServer::send_reliable(ClientId id, std::span<const std::uint8_t> message, TimeUs now,
                               Delivery delivery) {
  auto it = state_->clients.find(id);
  if (it == state_->clients.end() || message.empty() || message.size() > kMaxReliableMessageBytes) {
    return false;
  }
  if (it->second->connection.queue_reliable(message, delivery)) return true;
  if (delivery == Delivery::Droppable) {
    // The client is behind (slow, lossy or flooded): this one is not worth its connection.
    ++state_->counters.reliable_dropped;
    return false;
  }
  // The client has acked none of max_reliable_queued messages: it is gone or hostile.
  state_->remove_client(id, DisconnectReason::ReliableOverflow, true, now);
  return false;
}

void GameServer::disconnect(ClientId client, DisconnectReason reason, TimeUs now) {
  state_->remove_client(client, reason, true, now);
}

void GameServer::disconnect_all(DisconnectReason reason, TimeUs now) {
  std::vector<ClientId> ids;
  for (const auto& [id, client] : state_->clients) ids.push_back(id);
  for (ClientId id : ids) state_->remove_client(id, reason, true, now);
}

bool GameServer::connected(ClientId client) const {
  return state_->clients.contains(client);
}

std::size_t GameServer::client_count() const {
  return state_->clients.size();
}

TimeUs GameServer::rtt_us(ClientId client) const {
  auto it = state_->clients.find(client);
  return it == state_->clients.end() ? 0 : it->second->connection.rtt_us();
}

const TransportCounters& GameServer::counters() const {
  return state_->counters;
}

}  // namespace ricochet::proto
