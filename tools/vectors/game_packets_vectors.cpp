/// tests/vectors/game_packets.txt: the game channel's transport (PROTOCOL.md Game channel
/// transport) as the C++ end writes and reads it. Sequences are u64 written as int64 (bit 63 set
/// reads as a negative number); t_us is fake time in microseconds.
///   sealed type=NAME sequence=N protocol_id=N key=HEX body=HEX packet=HEX
///     proto::seal_packet(type, sequence, protocol_id, key, body) == packet, and opening packet
///     under key gives body back.
///   replay sequence=N accepted=0|1 ack=N ack_bits=N missing=N late=N
///     One ReplayWindow fed these sequences in order (a refused one is not marked); the ack
///     header and the loss figures after each.
///   session name=NAME
///     A scripted exchange between a proto::GameClient and, in the "handshake" session, a
///     proto::GameServer, with fixed keys, a fixed connect token and fixed time. Then, in order,
///     the client's inputs (one record each) and what each made the client do:
///   client_start t_us=N protocol_id=N timeout_s=N connect_token=HEX client_to_server_key=HEX
///                server_to_client_key=HEX
///   client_update t_us=N | client_receive t_us=N bytes=HEX | client_send_unreliable t_us=N
///     bytes=HEX | client_send_reliable t_us=N bytes=HEX | client_disconnect t_us=N
///   client_sends bytes=HEX                       a datagram, in the order sent
///   client_event kind=connected|unreliable|reliable|disconnected [bytes=HEX] [reason=NAME]
///   client_drop reason=NAME                      the datagram was refused, counted by reason
///   client_end state=NAME packets_in=N packets_out=N bytes_in=N bytes_out=N
///     The client's state and counters at the end of the session.
/// The server's random challenge key comes from libsodium's randombytes, which this writer
/// points at a fixed-seed generator (randombytes_set_implementation) while it runs, so that the
/// challenge bytes are the same on every run.

#include <sodium.h>

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "ricochet/proto/connect_token.h"
#include "ricochet/proto/crypto.h"
#include "ricochet/proto/game_client.h"
#include "ricochet/proto/game_server.h"
#include "ricochet/proto/packet.h"
#include "ricochet/proto/replay_window.h"
#include "ricochet/proto/token_grant.h"
#include "ricochet/proto/transport_counters.h"
#include "vector_file.h"

namespace ricochet::vectors {
namespace {

using Bytes = std::vector<std::uint8_t>;
using proto::TimeUs;
constexpr TimeUs kMs = proto::kMicrosPerMilli;

// ---- a fixed-seed randombytes for libsodium, while this writer runs ----

std::uint64_t fixed_random_draws = 0;

void fixed_random_buf(void* const out, const size_t size) {
  unsigned char seed[randombytes_SEEDBYTES] = {'r', 'i', 'c', 'o', 'c', 'h', 'e', 't'};
  for (int i = 0; i < 8; ++i)
    seed[8 + i] = static_cast<unsigned char>(fixed_random_draws >> (8 * i));
  ++fixed_random_draws;
  randombytes_buf_deterministic(out, size, seed);
}
uint32_t fixed_random_u32() {
  uint32_t value = 0;
  fixed_random_buf(&value, sizeof value);
  return value;
}
const char* fixed_random_name() {
  return "ricochet-vectors fixed seed";
}
void fixed_random_stir() {}
int fixed_random_close() {
  return 0;
}
randombytes_implementation fixed_random = {&fixed_random_name, &fixed_random_u32,
                                           &fixed_random_stir, nullptr,
                                           &fixed_random_buf,  &fixed_random_close};

/// Points libsodium's randombytes at the fixed seed for its lifetime.
class FixedRandom {
 public:
  FixedRandom() {
    fixed_random_draws = 0;
    randombytes_set_implementation(&fixed_random);
  }
  ~FixedRandom() { randombytes_set_implementation(&randombytes_internal_implementation); }
  FixedRandom(const FixedRandom&) = delete;
  FixedRandom& operator=(const FixedRandom&) = delete;
};

// ---- fixed inputs ----

proto::Key pattern_key(std::uint8_t start, std::uint8_t step) {
  proto::Key key;
  for (std::size_t i = 0; i < key.size(); ++i) key[i] = static_cast<std::uint8_t>(start + step * i);
  return key;
}

Bytes text(std::string_view s) {
  return Bytes(s.begin(), s.end());
}

const proto::Address kServer = proto::Address::ipv4(127, 0, 0, 1, 7778);
const proto::Address kClient = proto::Address::ipv4(127, 0, 0, 1, 50000);

/// A connect token sealed with a fixed nonce (proto::issue_connect_token draws one at random).
proto::TokenGrant fixed_grant(const proto::Key& token_key, std::uint64_t account_id,
                              TimeUs expires_at, std::uint32_t timeout_s) {
  proto::ConnectTokenContents contents;
  contents.account_id = account_id;
  contents.match_id = 7;
  contents.expires_at = expires_at;
  contents.timeout_s = timeout_s;
  contents.client_to_server = pattern_key(0x10, 3);
  contents.server_to_client = pattern_key(0x80, 5);
  proto::XNonce nonce;
  for (std::size_t i = 0; i < nonce.size(); ++i) nonce[i] = static_cast<std::uint8_t>(0xA0 + i);
  const Bytes plain = proto::encode_connect_token_plaintext(contents);
  const auto ad = proto::version_and_protocol(proto::kProtocolId);
  proto::TokenGrant grant;
  grant.connect_token.assign(nonce.begin(), nonce.end());
  proto::seal_xchacha(plain, ad, nonce, token_key, grant.connect_token);
  grant.client_to_server = contents.client_to_server;
  grant.server_to_client = contents.server_to_client;
  grant.expires_at = expires_at;
  grant.timeout_s = timeout_s;
  return grant;
}

// ---- sealed packets and the replay window ----

void add_sealed(VectorFile& file) {
  file.comment("sealed packets of every encrypted type");
  const proto::Key key = pattern_key(0x42, 7);
  proto::ChallengeBody challenge;
  challenge.challenge_sequence = 9;
  for (std::size_t i = 0; i < challenge.challenge_token.size(); ++i) {
    challenge.challenge_token[i] = static_cast<std::uint8_t>(i * 11);
  }
  proto::PayloadBody payload;
  payload.ack = {0x1234, 0x80000001u};
  payload.reliable = {{65535, text("event")}, {0, text("next")}};
  payload.unreliable = text("snapshot bytes");
  proto::PayloadBody empty_payload;
  empty_payload.ack = {7, 0x3Fu};
  struct Case {
    proto::PacketType type;
    std::uint64_t sequence;
    Bytes body;
  };
  const Case cases[] = {
      {proto::PacketType::ConnectionDenied, proto::kHandshakeSequenceBit | 3,
       proto::write_denied_body(proto::DisconnectReason::Denied)},
      {proto::PacketType::ConnectionDenied, proto::kHandshakeSequenceBit | 4,
       proto::write_denied_body(proto::DisconnectReason::HostFull)},
      {proto::PacketType::Challenge, proto::kHandshakeSequenceBit,
       proto::write_challenge_body(challenge)},
      {proto::PacketType::Response, 0, proto::write_challenge_body(challenge)},
      {proto::PacketType::KeepAlive, 1, proto::write_keep_alive_body({0, 0})},
      {proto::PacketType::KeepAlive, 0x1'0000'0001ull, proto::write_keep_alive_body({65535, ~0u})},
      {proto::PacketType::Payload, 2, proto::write_payload_body(payload)},
      {proto::PacketType::Payload, 3, proto::write_payload_body(empty_payload)},
      {proto::PacketType::Disconnect, 4,
       proto::write_disconnect_body({{3, 0x5u}, proto::DisconnectReason::Kicked})},
      {proto::PacketType::Disconnect, 5,
       proto::write_disconnect_body({{4, 0xBu}, proto::DisconnectReason::Banned})},
  };
  for (const Case& c : cases) {
    const Bytes packet = proto::seal_packet(c.type, c.sequence, proto::kProtocolId, key, c.body);
    Bytes opened;
    if (!proto::open_packet(packet, proto::kProtocolId, key, opened) || opened != c.body) {
      throw std::logic_error("a sealed vector does not open");
    }
    file.add(Record("sealed")
                 .word("type", proto::name(c.type))
                 .number("sequence", static_cast<std::int64_t>(c.sequence))
                 .number("protocol_id", static_cast<std::int64_t>(proto::kProtocolId))
                 .bytes("key", key)
                 .bytes("body", c.body)
                 .bytes("packet", packet));
  }
}

void add_replay(VectorFile& file) {
  file.comment("one replay window fed these sequences in order");
  proto::ReplayWindow window;
  const std::uint64_t sequences[] = {0,   1,   2,   5,    3,   3,   4,   0,    300,  44,   45,
                                     299, 301, 298, 1000, 745, 744, 999, 1000, 1063, 1031, 1032};
  for (std::uint64_t sequence : sequences) {
    const bool accepted = !window.already_received(sequence);
    if (accepted) window.mark_received(sequence);
    const proto::AckHeader ack = window.ack_header();
    file.add(Record("replay")
                 .number("sequence", static_cast<std::int64_t>(sequence))
                 .number("accepted", accepted ? 1 : 0)
                 .number("ack", ack.ack)
                 .number("ack_bits", ack.ack_bits)
                 .number("missing", static_cast<std::int64_t>(window.missing()))
                 .number("late", static_cast<std::int64_t>(window.late())));
  }
}

// ---- scripted sessions ----

/// Drives one GameClient and records every input it gets and everything it does.
class ClientScript {
 public:
  ClientScript(VectorFile& file, const proto::TokenGrant& grant, TimeUs now) : file_(file) {
    file_.add(Record("client_start")
                  .number("t_us", now)
                  .number("protocol_id", static_cast<std::int64_t>(proto::kProtocolId))
                  .number("timeout_s", grant.timeout_s)
                  .bytes("connect_token", grant.connect_token)
                  .bytes("client_to_server_key", grant.client_to_server)
                  .bytes("server_to_client_key", grant.server_to_client));
    client_.emplace(proto::ClientConnectInfo{grant, proto::kProtocolId, kServer}, now);
    drops_ = client_->counters().drops;
    record_effects();
  }

  void update(TimeUs now) {
    file_.add(Record("client_update").number("t_us", now));
    client_->update(now);
    record_effects();
  }
  void receive(std::span<const std::uint8_t> datagram, TimeUs now) {
    file_.add(Record("client_receive").number("t_us", now).bytes("bytes", datagram));
    client_->receive(kServer, datagram, now);
    record_effects();
  }
  void send_unreliable(std::span<const std::uint8_t> bytes, TimeUs now) {
    file_.add(Record("client_send_unreliable").number("t_us", now).bytes("bytes", bytes));
    if (!client_->send_unreliable(bytes, now)) throw std::logic_error("send_unreliable refused");
    record_effects();
  }
  void send_reliable(std::span<const std::uint8_t> bytes, TimeUs now) {
    file_.add(Record("client_send_reliable").number("t_us", now).bytes("bytes", bytes));
    if (!client_->send_reliable(bytes, now)) throw std::logic_error("send_reliable refused");
    record_effects();
  }
  void disconnect(TimeUs now) {
    file_.add(Record("client_disconnect").number("t_us", now));
    client_->disconnect(now);
    record_effects();
  }
  void end() {
    const proto::TransportCounters& counters = client_->counters();
    file_.add(Record("client_end")
                  .word("state", proto::name(client_->state()))
                  .number("packets_in", static_cast<std::int64_t>(counters.packets_in))
                  .number("packets_out", static_cast<std::int64_t>(counters.packets_out))
                  .number("bytes_in", static_cast<std::int64_t>(counters.bytes_in))
                  .number("bytes_out", static_cast<std::int64_t>(counters.bytes_out)));
  }

  /// The datagrams the client sent since the last call, for the script to deliver or lose.
  std::vector<Bytes> take_sent() { return std::exchange(sent_, {}); }

 private:
  void record_effects() {
    proto::Transmit transmit;
    while (client_->poll_transmit(transmit)) {
      file_.add(Record("client_sends").bytes("bytes", transmit.bytes));
      sent_.push_back(transmit.bytes);
    }
    const auto& drops = client_->counters().drops;
    for (std::size_t i = 0; i < drops.size(); ++i) {
      for (std::uint64_t n = drops_[i]; n < drops[i]; ++n) {
        file_.add(
            Record("client_drop").word("reason", proto::name(static_cast<proto::DropReason>(i))));
      }
    }
    drops_ = drops;
    proto::ClientEvent event;
    while (client_->poll_event(event)) {
      if (std::holds_alternative<proto::ClientConnected>(event)) {
        file_.add(Record("client_event").word("kind", "connected"));
      } else if (auto* d = std::get_if<proto::ClientDisconnected>(&event)) {
        file_.add(Record("client_event")
                      .word("kind", "disconnected")
                      .word("reason", proto::name(d->reason)));
      } else if (auto* u = std::get_if<proto::ClientUnreliable>(&event)) {
        file_.add(Record("client_event").word("kind", "unreliable").bytes("bytes", u->bytes));
      } else if (auto* r = std::get_if<proto::ClientReliable>(&event)) {
        file_.add(Record("client_event").word("kind", "reliable").bytes("bytes", r->bytes));
      }
    }
  }

  VectorFile& file_;
  std::optional<proto::GameClient> client_;
  std::array<std::uint64_t, proto::kDropReasonCount> drops_{};
  std::vector<Bytes> sent_;
};

/// The server end of the handshake session.
class ServerSide {
 public:
  explicit ServerSide(const proto::Key& token_key) : server_(config(token_key)) {}

  /// Delivers the client's datagrams; returns the server's datagrams since the last call.
  std::vector<Bytes> deliver(const std::vector<Bytes>& datagrams, TimeUs now) {
    for (const Bytes& datagram : datagrams) server_.receive(kClient, datagram, now);
    return drain();
  }
  std::vector<Bytes> update(TimeUs now) {
    server_.update(now);
    return drain();
  }
  proto::GameServer& server() { return server_; }
  proto::ClientId client() const { return client_; }

 private:
  static proto::GameServerConfig config(const proto::Key& token_key) {
    proto::GameServerConfig config;
    config.protocol_id = proto::kProtocolId;
    config.token_key = token_key;
    return config;
  }
  std::vector<Bytes> drain() {
    std::vector<Bytes> out;
    proto::Transmit transmit;
    while (server_.poll_transmit(transmit)) {
      if (transmit.to != kClient) throw std::logic_error("server sent elsewhere");
      out.push_back(transmit.bytes);
    }
    proto::ServerEvent event;
    while (server_.poll_event(event)) {
      if (auto* connected = std::get_if<proto::ServerConnected>(&event))
        client_ = connected->client;
    }
    return out;
  }

  proto::GameServer server_;
  proto::ClientId client_ = 0;
};

void deliver_all(ClientScript& client, const std::vector<Bytes>& datagrams, TimeUs now) {
  for (const Bytes& datagram : datagrams) client.receive(datagram, now);
}

Bytes tampered(Bytes datagram, std::size_t at) {
  datagram.at(at) ^= 0x01;
  return datagram;
}

/// Handshake with a lost challenge, events in and out of order, keep-alives both ways, refused
/// datagrams of every kind a connected client can see, and the server's disconnect.
void add_handshake_session(VectorFile& file) {
  file.comment("the client against a GameServer: handshake, traffic, refusals, kicked");
  file.add(Record("session").word("name", "handshake"));
  const proto::Key token_key = pattern_key(0x01, 1);
  TimeUs t = 10'000 * kMs;
  const proto::TokenGrant grant = fixed_grant(token_key, 42, t + 10'000 * kMs, 5);
  ServerSide server(token_key);
  ClientScript client(file, grant, t);

  // The first challenge is lost; the client resends its request 100 ms later, not before.
  server.deliver(client.take_sent(), t);
  client.update(t + 50 * kMs);
  client.update(t + 100 * kMs);
  std::vector<Bytes> challenge = server.deliver(client.take_sent(), t + 101 * kMs);
  deliver_all(client, challenge, t + 110 * kMs);
  deliver_all(client, challenge, t + 111 * kMs);  // a duplicate challenge: ignored
  std::vector<Bytes> keep_alive = server.deliver(client.take_sent(), t + 120 * kMs);
  deliver_all(client, keep_alive, t + 130 * kMs);
  const proto::ClientId id = server.client();
  if (id == 0) throw std::logic_error("the handshake did not connect");

  // Two payloads with reliable events, delivered in reverse order, then one again.
  proto::GameServer& s = server.server();
  const std::vector<std::uint8_t> event1 = text("event one"), event2 = text("event two"),
                                  event3 = text("event three");
  s.send_reliable(id, event1, t + 150 * kMs);
  s.send_reliable(id, event2, t + 150 * kMs);
  s.send_unreliable(id, text("snapshot one"), t + 150 * kMs);
  std::vector<Bytes> first = server.update(t + 150 * kMs);
  s.send_reliable(id, event3, t + 160 * kMs);
  s.send_unreliable(id, text("snapshot two"), t + 160 * kMs);
  std::vector<Bytes> second = server.update(t + 160 * kMs);
  deliver_all(client, second, t + 170 * kMs);
  deliver_all(client, first, t + 175 * kMs);
  deliver_all(client, first, t + 176 * kMs);  // replayed

  // The client's input, a reliable message of its own, then keep-alives while idle.
  client.send_unreliable(text("input 1"), t + 180 * kMs);
  client.send_reliable(text("client hello"), t + 185 * kMs);
  client.update(t + 190 * kMs);
  for (TimeUs at = t + 200 * kMs; at <= t + 600 * kMs; at += 20 * kMs) {
    server.deliver(client.take_sent(), at);
    deliver_all(client, server.update(at), at + 5 * kMs);
    client.update(at + 10 * kMs);
  }
  server.deliver(client.take_sent(), t + 610 * kMs);

  // Refusals while connected.
  TimeUs at = t + 620 * kMs;
  std::vector<Bytes> fresh = server.update(t + 700 * kMs);
  if (fresh.empty()) throw std::logic_error("no keep-alive to tamper with");
  const Bytes& good = fresh.front();
  client.receive({}, at);
  client.receive(Bytes(1201, 4), at);
  client.receive(Bytes{9, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
                       0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0},
                 at);
  client.receive(Bytes(good.begin(), good.end() - 1), at);  // truncated
  client.receive(tampered(good, good.size() - 1), at);      // tag
  client.receive(tampered(good, 4), at);                    // sequence
  client.receive(tampered(good, 0), at);  // keep-alive made a payload: too short for one
  client.receive(challenge.front(), at);  // wrong_state
  const std::uint64_t ahead = 200;        // within the window of the server's next sequences
  const auto seal = [&](proto::PacketType type, std::uint64_t sequence, const Bytes& body) {
    return proto::seal_packet(type, sequence, proto::kProtocolId, grant.server_to_client, body);
  };
  client.receive(seal(proto::PacketType::KeepAlive, ahead, Bytes(7, 0)), at);  // malformed
  client.receive(
      seal(proto::PacketType::Payload, ahead + 1, Bytes{0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0}),
      at);  // a reliable message of length 0: malformed
  client.receive(
      seal(proto::PacketType::Payload, ahead + 2, Bytes{0, 0, 0, 0, 0, 0, 1, 0, 0, 9, 0, 'x'}),
      at);  // one that runs past the body: truncated
  client.receive(seal(proto::PacketType::Disconnect, ahead + 3, Bytes{0, 0, 0, 0, 0, 0, 12}),
                 at);  // reason 12: malformed
  client.receive(
      seal(proto::PacketType::Payload, ahead + 4, Bytes{0, 0, 0, 0, 0, 0, 1, 0, 2, 1, 0, 'z'}),
      at);  // a reliable id 512 ahead: reliable_out_of_window, the packet still used
  deliver_all(client, fresh, at + kMs);  // the genuine one still opens
  // Its keep-alive acks 204: the refused bodies above authenticated, so they count as received.
  client.update(t + 700 * kMs);

  // The match is over: the server kicks the client; the other two copies find it disconnected.
  s.disconnect(id, proto::DisconnectReason::Kicked, t + 800 * kMs);
  deliver_all(client, server.update(t + 800 * kMs), t + 810 * kMs);
  client.update(t + 900 * kMs);
  client.end();
}

/// A lossy session that the client ends: a lost payload's reliable event resent by the server,
/// a reordered keep-alive, then the client's three disconnect packets.
void add_leave_session(VectorFile& file) {
  file.comment("the client against a GameServer over loss; the client leaves");
  file.add(Record("session").word("name", "leave"));
  const proto::Key token_key = pattern_key(0x21, 3);
  TimeUs t = 40'000 * kMs;
  const proto::TokenGrant grant = fixed_grant(token_key, 45, t + 10'000 * kMs, 2);
  ServerSide server(token_key);
  ClientScript client(file, grant, t);
  deliver_all(client, server.deliver(client.take_sent(), t + 5 * kMs), t + 10 * kMs);
  deliver_all(client, server.deliver(client.take_sent(), t + 15 * kMs), t + 20 * kMs);
  const proto::ClientId id = server.client();
  if (id == 0) throw std::logic_error("the leave session did not connect");
  proto::GameServer& s = server.server();
  s.send_reliable(id, text("spawned"), t + 30 * kMs);
  server.update(t + 30 * kMs);  // lost
  std::vector<Bytes> late;
  for (TimeUs at = t + 40 * kMs; at <= t + 400 * kMs; at += 40 * kMs) {
    s.send_unreliable(id, text("tick"), at);
    std::vector<Bytes> out = server.update(at);
    if (at == t + 80 * kMs) {
      late = out;  // delivered after the next one
      continue;
    }
    deliver_all(client, out, at + 3 * kMs);
    if (at == t + 120 * kMs) deliver_all(client, late, at + 4 * kMs);
    client.send_unreliable(text("in"), at + 5 * kMs);
    client.update(at + 6 * kMs);
    server.deliver(client.take_sent(), at + 8 * kMs);
  }
  client.disconnect(t + 410 * kMs);
  server.deliver(client.take_sent(), t + 415 * kMs);
  client.update(t + 500 * kMs);
  client.end();
}

/// Connected, then the server goes silent: keep-alives at 10 Hz, then timed_out at timeout_s.
void add_timeout_session(VectorFile& file) {
  file.comment("a connected client whose server goes silent");
  file.add(Record("session").word("name", "timeout"));
  const proto::Key token_key = pattern_key(0x31, 5);
  TimeUs t = 50'000 * kMs;
  const proto::TokenGrant grant = fixed_grant(token_key, 46, t + 10'000 * kMs, 1);
  ServerSide server(token_key);
  ClientScript client(file, grant, t);
  deliver_all(client, server.deliver(client.take_sent(), t), t + kMs);
  deliver_all(client, server.deliver(client.take_sent(), t + kMs), t + 2 * kMs);
  for (TimeUs at = t + 25 * kMs; at <= t + 1'100 * kMs; at += 25 * kMs) client.update(at);
  client.end();
}

/// Before a challenge: what a client sending requests refuses, and a denied packet.
void add_denied_session(VectorFile& file) {
  file.comment("a client refused by a full server; what it drops before the challenge");
  file.add(Record("session").word("name", "denied"));
  TimeUs t = 20'000 * kMs;
  const proto::TokenGrant grant = fixed_grant(pattern_key(0x55, 1), 43, t + 10'000 * kMs, 3);
  ClientScript client(file, grant, t);
  const auto seal = [&](proto::PacketType type, std::uint64_t sequence, const Bytes& body,
                        const proto::Key& key) {
    return proto::seal_packet(type, sequence, proto::kProtocolId, key, body);
  };
  const proto::Key& key = grant.server_to_client;
  client.receive(seal(proto::PacketType::KeepAlive, 0, Bytes(6, 0), key), t);  // wrong_state
  client.receive(seal(proto::PacketType::ConnectionDenied, 1,
                      proto::write_denied_body(proto::DisconnectReason::Denied), key),
                 t);  // no handshake bit: malformed
  client.receive(
      seal(proto::PacketType::ConnectionDenied, proto::kHandshakeSequenceBit,
           proto::write_denied_body(proto::DisconnectReason::Denied), grant.client_to_server),
      t);  // the wrong key: forged_mac
  client.receive(
      seal(proto::PacketType::ConnectionDenied, proto::kHandshakeSequenceBit | 1, Bytes{12}, key),
      t);  // malformed reason
  client.receive(
      seal(proto::PacketType::Challenge, proto::kHandshakeSequenceBit | 2, Bytes(70, 1), key),
      t);  // a challenge body one byte short: malformed
  client.update(t + 100 * kMs);
  client.receive(seal(proto::PacketType::ConnectionDenied, proto::kHandshakeSequenceBit | 3,
                      proto::write_denied_body(proto::DisconnectReason::HostFull), key),
                 t + 120 * kMs);
  client.update(t + 300 * kMs);
  client.end();
}

/// No answer at all: requests at 10 Hz until timeout_s, then handshake_timed_out.
void add_silent_session(VectorFile& file) {
  file.comment("a client whose server never answers");
  file.add(Record("session").word("name", "silent"));
  TimeUs t = 30'000 * kMs;
  const proto::TokenGrant grant = fixed_grant(pattern_key(0x66, 1), 44, t + 10'000 * kMs, 1);
  ClientScript client(file, grant, t);
  for (TimeUs at = t + 50 * kMs; at <= t + 1'000 * kMs; at += 50 * kMs) client.update(at);
  client.end();
}

}  // namespace

std::string write_game_packets_vectors() {
  FixedRandom fixed_random_while_writing;
  VectorFile file("game_packets",
                  "the game channel's packets, replay window and scripted sessions of the C++ "
                  "client (tools/vectors/game_packets_vectors.cpp says what each record means)");
  add_sealed(file);
  add_replay(file);
  add_handshake_session(file);
  add_leave_session(file);
  add_timeout_session(file);
  add_denied_session(file);
  add_silent_session(file);
  return file.text();
}

}  // namespace ricochet::vectors
