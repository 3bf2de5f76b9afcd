#include "ricochet/proto/game_client.h"

#include "connection.h"
#include "ricochet/proto/packet.h"
#include "ricochet/proto/transport_states.h"
#include "transmit_queue.h"

namespace ricochet::proto {
struct GameClient::State {
  ClientConnectInfo info;
  GameClientConfig config;
  Connection connection;
  ConnectionState state = ConnectionState::SendingRequest;
  std::optional<DisconnectReason> reason;
  std::optional<ChallengeBody> challenge;  ///< echoed in every response
  std::vector<std::uint8_t> request;       ///< the same bytes every time
  TimeUs last_handshake_send = 0;
  TimeUs handshake_deadline = 0;
  TransmitQueue transmits;
  std::deque<ClientEvent> events;
  TransportCounters counters;

  State(ClientConnectInfo connect, GameClientConfig client_config, TimeUs now)
      : info(std::move(connect)),
        config(std::move(client_config)),
        connection(info.protocol_id, info.grant.client_to_server, info.grant.server_to_client,
                   {static_cast<TimeUs>(info.grant.timeout_s) * kMicrosPerSecond,
                    config.keep_alive_us, config.reliable_resend_us, config.max_reliable_pending},
                   now),
        request(write_connection_request(info.protocol_id, info.grant.connect_token)),
        handshake_deadline(now + static_cast<TimeUs>(info.grant.timeout_s) * kMicrosPerSecond) {}

  void drop(DropReason drop_reason, const Address& from) {
    ++counters.drops[static_cast<std::size_t>(drop_reason)];
    if (config.log.on_drop) config.log.on_drop(drop_reason, from);
  }
  void send(std::vector<std::uint8_t> bytes) {
    count_sent(bytes.size());
    transmits.push(info.server, std::move(bytes));
  }
  void send_payload(std::span<const std::uint8_t> unreliable, TimeUs now) {
    std::vector<std::uint8_t>& packet = transmits.push(info.server);
    connection.make_payload(unreliable, now, packet);
    count_sent(packet.size());
  }
  void count_sent(std::size_t bytes) {
    ++counters.packets_out;
    counters.bytes_out += bytes;
  }
  void enter(ConnectionState to, std::string_view why) {
    if (config.log.on_transition) config.log.on_transition({info.server, 0, state, to, why});
    state = to;
  }
  void end(DisconnectReason why) {
    ++counters.disconnects[static_cast<std::size_t>(why)];
    reason = why;
    enter(ConnectionState::Disconnected, name(why));
    events.push_back(ClientDisconnected{why});
  }
  /// This end's decision to stop: tells the server when connected, then ends.
  void leave(DisconnectReason why, TimeUs now) {
    if (state == ConnectionState::Connected) {
      for (int copy = 0; copy < kDisconnectCopies; ++copy) {
        send(connection.make_disconnect(why, now));
      }
    }
    end(why);
  }
  void send_handshake(TimeUs now) {
    last_handshake_send = now;
    if (state == ConnectionState::SendingRequest) {
      send(request);
    } else {
      send(connection.seal(PacketType::Response, write_challenge_body(*challenge), now));
    }
  }
  void become_connected() {
    enter(ConnectionState::Connected, "first keep-alive or payload from the server");
    ++counters.connections_total;
    events.push_back(ClientConnected{});
  }

  void on_handshake_packet(const EncryptedHeader& header, std::span<const std::uint8_t> datagram,
                           TimeUs now);
  void on_session_packet(const EncryptedHeader& header, std::span<const std::uint8_t> datagram,
                         TimeUs now);
};

void GameClient::State::on_handshake_packet(const EncryptedHeader& header,
                                            std::span<const std::uint8_t> datagram, TimeUs now) {
  // Challenge and denied carry server-wide handshake sequences outside the session's replay
  // window; a replayed one is harmless (a second challenge is ignored, denied ends anyway).
  if ((header.sequence & kHandshakeSequenceBit) == 0) {
    return drop(DropReason::Malformed, info.server);
  }
  std::vector<std::uint8_t> body;
  if (!open_packet(datagram, info.protocol_id, info.grant.server_to_client, body)) {
    return drop(DropReason::ForgedMac, info.server);
  }
  if (header.type == PacketType::ConnectionDenied) {
    auto denied = read_denied_body(body);
    if (!denied.ok()) return drop(*denied.error, info.server);
    return end(denied.value);  // Denied (server full) or HostFull
  }
  auto parsed = read_challenge_body(body);
  if (!parsed.ok()) return drop(*parsed.error, info.server);
  if (state != ConnectionState::SendingRequest) return;  // a duplicate: the response is going out
  challenge = parsed.value;
  enter(ConnectionState::SendingResponse, "challenge received");
  handshake_deadline = now + static_cast<TimeUs>(info.grant.timeout_s) * kMicrosPerSecond;
  send_handshake(now);
}

void GameClient::State::on_session_packet(const EncryptedHeader& header,
                                          std::span<const std::uint8_t> datagram, TimeUs now) {
  std::vector<std::uint8_t> body;
  if (auto error = connection.open(header, datagram, body, now)) return drop(*error, info.server);
  switch (header.type) {
    case PacketType::KeepAlive: {
      auto ack = read_keep_alive_body(body);
      if (!ack.ok()) return drop(*ack.error, info.server);
      if (state == ConnectionState::SendingResponse) become_connected();
      connection.on_ack(ack.value, now);
      return;
    }
    case PacketType::Payload: {
      auto payload = read_payload_body(body);
      if (!payload.ok()) return drop(*payload.error, info.server);
      if (state == ConnectionState::SendingResponse) become_connected();
      connection.on_ack(payload.value.ack, now);
      if (!connection.on_reliable(payload.value.reliable)) {
        drop(DropReason::ReliableOutOfWindow, info.server);
      }
      std::vector<std::uint8_t> message;
      while (connection.pop_reliable(message)) events.push_back(ClientReliable{std::move(message)});
      if (!payload.value.unreliable.empty()) {
        events.push_back(ClientUnreliable{std::move(payload.value.unreliable)});
      }
      return;
    }
    case PacketType::Disconnect: {
      auto disconnect = read_disconnect_body(body);
      if (!disconnect.ok()) return drop(*disconnect.error, info.server);
      // The server's reason (Replaced, Kicked, ServerShutdown...) is what the client reports.
      return end(disconnect.value.reason);
    }
    default:
      return drop(DropReason::WrongState, info.server);
  }
}

GameClient::GameClient(ClientConnectInfo info, TimeUs now, GameClientConfig config)
    : state_(std::make_unique<State>(std::move(info), std::move(config), now)) {
  state_->enter(ConnectionState::SendingRequest, "connect token received");
  state_->send_handshake(now);
}

GameClient::~GameClient() = default;

void GameClient::receive(const Address& from, std::span<const std::uint8_t> datagram, TimeUs now) {
  State& s = *state_;
  ++s.counters.packets_in;
  s.counters.bytes_in += datagram.size();
  if (from != s.info.server) return s.drop(DropReason::UnknownAddress, from);
  auto header = read_encrypted_header(datagram);
  if (!header.ok()) return s.drop(*header.error, from);
  if (!client_accepts(s.state, header.value.type)) return s.drop(DropReason::WrongState, from);
  if (header.value.type == PacketType::Challenge ||
      header.value.type == PacketType::ConnectionDenied) {
    return s.on_handshake_packet(header.value, datagram, now);
  }
  s.on_session_packet(header.value, datagram, now);
}

void GameClient::update(TimeUs now) {
  State& s = *state_;
  switch (s.state) {
    case ConnectionState::SendingRequest:
    case ConnectionState::SendingResponse:
      if (now >= s.handshake_deadline) return s.end(DisconnectReason::HandshakeTimedOut);
      if (now - s.last_handshake_send >= s.config.resend_us) s.send_handshake(now);
      return;
    case ConnectionState::Connected:
      if (s.connection.timed_out(now)) return s.end(DisconnectReason::TimedOut);
      if (s.connection.reliable_due(now)) {
        s.send_payload({}, now);
      } else if (s.connection.keep_alive_due(now)) {
        s.send(s.connection.make_keep_alive(now));
      }
      s.counters.reliable_resends = s.connection.reliable_resends();
      return;
    default:
      return;
  }
}

bool GameClient::poll_transmit(Transmit& out) {
  return state_->transmits.pop(out);
}

bool GameClient::poll_event(ClientEvent& out) {
  if (state_->events.empty()) return false;
  out = std::move(state_->events.front());
  state_->events.pop_front();
  return true;
}

bool GameClient::send_unreliable(std::span<const std::uint8_t> payload, TimeUs now) {
  if (state_->state != ConnectionState::Connected || payload.size() > kMaxUnreliableBytes) {
    return false;
  }
  state_->send_payload(payload, now);
  return true;
}

bool GameClient::send_reliable(std::span<const std::uint8_t> message, TimeUs now) {
  State& s = *state_;
  if (s.state == ConnectionState::Disconnected || message.empty() ||
      message.size() > kMaxReliableMessageBytes) {
    return false;
  }
  if (s.connection.queue_reliable(message, Delivery::MustArrive)) return true;
  s.leave(DisconnectReason::ReliableOverflow, now);
  return false;
}

void GameClient::disconnect(TimeUs now) {
  if (state_->state != ConnectionState::Disconnected)
    state_->leave(DisconnectReason::Requested, now);
}

ConnectionState GameClient::state() const {
  return state_->state;
}

std::optional<DisconnectReason> GameClient::disconnect_reason() const {
  return state_->reason;
}

TimeUs GameClient::rtt_us() const {
  return state_->connection.rtt_us();
}

const TransportCounters& GameClient::counters() const {
  return state_->counters;
}

GameClient::ReceiveStats GameClient::receive_stats() const {
  const ReplayWindow& received = state_->connection.received();
  if (!received.any_received()) return {};
  return {received.newest() + 1, received.missing(), received.late()};
}

}  // namespace ricochet::proto
