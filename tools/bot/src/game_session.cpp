#include "ricochet/bot/game_session.h"

#include <spdlog/spdlog.h>

#include <chrono>

namespace ricochet::bot {

namespace asio = boost::asio;

proto::TimeUs steady_now_us() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

proto::Address to_address(const asio::ip::udp::endpoint& endpoint) {
  proto::Address address;
  address.port = endpoint.port();
  if (endpoint.address().is_v4()) {
    const auto bytes = endpoint.address().to_v4().to_bytes();
    std::copy(bytes.begin(), bytes.end(), address.ip.begin());
  } else {
    const auto bytes = endpoint.address().to_v6().to_bytes();
    std::copy(bytes.begin(), bytes.end(), address.ip.begin());
    address.v6 = true;
  }
  return address;
}

namespace {

proto::ClientConnectInfo connect_info(const asio::ip::udp::endpoint& server,
                                      proto::TokenGrant grant) {
  proto::ClientConnectInfo info;
  info.grant = std::move(grant);
  info.protocol_id = proto::kProtocolId;
  info.server = to_address(server);
  return info;
}

asio::ip::udp::endpoint any_local(const asio::ip::udp::endpoint& server) {
  return {server.address().is_v4() ? asio::ip::address(asio::ip::address_v4::any())
                                   : asio::ip::address(asio::ip::address_v6::any()),
          0};
}

}  // namespace

GameSession::GameSession(asio::io_context& io, const asio::ip::udp::endpoint& server,
                         proto::TokenGrant grant, EventHandler on_event)
    : socket_(io, any_local(server)),
      server_(server),
      client_(connect_info(server, std::move(grant)), steady_now_us()),
      on_event_(std::move(on_event)) {
  socket_.non_blocking(true);
  local_port_ = socket_.local_endpoint().port();
}

std::string GameSession::bind_local(const asio::ip::address& local) {
  boost::system::error_code error;
  socket_.close(error);
  socket_.open(local.is_v4() ? asio::ip::udp::v4() : asio::ip::udp::v6(), error);
  if (!error) socket_.bind({local, 0}, error);
  if (!error) socket_.non_blocking(true, error);
  if (error) return "cannot bind a UDP socket to " + local.to_string() + ": " + error.message();
  local_port_ = socket_.local_endpoint().port();
  return {};
}

void GameSession::start() {
  flush();
  wait_readable();
}

void GameSession::wait_readable() {
  socket_.async_wait(asio::ip::udp::socket::wait_read,
                     [self = shared_from_this()](const boost::system::error_code& error) {
                       if (self->closed_ || error) return;
                       self->drain(steady_now_us());
                       if (!self->closed_) self->wait_readable();
                     });
}

void GameSession::drain(proto::TimeUs now) {
  asio::ip::udp::endpoint from;
  for (int i = 0; i < 64 && !closed_; ++i) {
    boost::system::error_code error;
    const std::size_t size = socket_.receive_from(asio::buffer(buffer_), from, 0, error);
    if (error == asio::error::would_block) break;
    if (error) {
      // An ICMP error from an earlier send (port unreachable) surfaces here; the transport's
      // timeout decides whether the connection is lost.
      spdlog::debug("game: receive failed: {}", error.message());
      continue;
    }
    client_.receive(to_address(from), std::span<const std::uint8_t>(buffer_.data(), size), now);
  }
  flush();
}

void GameSession::update(proto::TimeUs now) {
  if (closed_) return;
  client_.update(now);
  flush();
}

bool GameSession::send(std::span<const std::uint8_t> payload, proto::TimeUs now) {
  if (closed_) return false;
  const bool sent = client_.send_unreliable(payload, now);
  flush();
  return sent;
}

void GameSession::disconnect(proto::TimeUs now) {
  if (closed_) return;
  client_.disconnect(now);
  send_queued();  // the disconnect packets; the event it queues is nobody's news
  abandon();
}

void GameSession::abandon() {
  if (closed_) return;
  // on_event_ stays (it may be the caller): closed_ stops every further event.
  closed_ = true;
  boost::system::error_code ignored;
  socket_.close(ignored);
}

void GameSession::send_queued() {
  proto::Transmit transmit;
  while (!closed_ && client_.poll_transmit(transmit)) {
    boost::system::error_code error;
    socket_.send_to(asio::buffer(transmit.bytes), server_, 0, error);
    if (error) ++send_failures_;
  }
}

void GameSession::flush() {
  send_queued();
  proto::ClientEvent event;
  while (!closed_ && client_.poll_event(event)) {
    if (on_event_) on_event_(event);
  }
}

}  // namespace ricochet::bot
