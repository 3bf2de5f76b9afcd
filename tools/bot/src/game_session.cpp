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
                         proto::TokenGrant grant, EventHandler on_event, const LinkConfig& link,
                         std::uint64_t link_seed)
    : socket_(io, any_local(server)),
      server_(server),
      client_(connect_info(server, std::move(grant)), steady_now_us()),
      on_event_(std::move(on_event)),
      link_timer_(io) {
  socket_.non_blocking(true);
  local_port_ = socket_.local_endpoint().port();
  if (link.active()) {
    up_.emplace(link, link_seed);
    down_.emplace(link, link_seed ^ 0x9E3779B97F4A7C15ull);
  }
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

std::string GameSession::use_shared_port(std::shared_ptr<SharedGamePort> port) {
  if (!server_.address().is_v4() || !server_.address().is_loopback()) {
    return "a shared game socket needs an IPv4 loopback server, got " +
           server_.address().to_string();
  }
  const auto address = port->attach(weak_from_this());
  if (!address) return "the shared game socket ran out of source addresses";
  boost::system::error_code ignored;
  socket_.close(ignored);
  shared_port_ = std::move(port);
  shared_address_ = *address;
  local_port_ = shared_port_->port();
  return {};
}

void GameSession::start() {
  flush(steady_now_us());
  if (!shared_port_) wait_readable();
}

void GameSession::receive_datagram(const asio::ip::udp::endpoint& from,
                                   std::span<const std::uint8_t> bytes, proto::TimeUs now) {
  if (closed_) return;
  take(from, bytes, now);
  flush(now);
}

void GameSession::take(const asio::ip::udp::endpoint& from, std::span<const std::uint8_t> bytes,
                       proto::TimeUs now) {
  if (down_ && from == server_) {
    down_->send({bytes.begin(), bytes.end()}, now);  // through the simulated link first
  } else {
    client_.receive(to_address(from), bytes, now);
  }
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
    take(from, std::span<const std::uint8_t>(buffer_.data(), size), now);
  }
  flush(now);
}

void GameSession::pump_links(proto::TimeUs now) {
  if (!up_ || closed_) return;
  std::vector<std::uint8_t> datagram;
  while (up_->poll(now, datagram)) transmit(datagram);
  bool received = false;
  while (!closed_ && down_->poll(now, datagram)) {
    client_.receive(to_address(server_), datagram, now);
    received = true;
  }
  if (received) flush(now);  // replies (acks) go into the up link, events out
  if (closed_) return;
  std::optional<proto::TimeUs> due = up_->next_due();
  if (const auto down_due = down_->next_due()) due = due ? std::min(*due, *down_due) : *down_due;
  if (!due || *due == link_armed_for_) return;
  link_armed_for_ = *due;
  link_timer_.expires_at(asio::steady_timer::time_point(std::chrono::microseconds(*due)));
  link_timer_.async_wait([self = shared_from_this()](const boost::system::error_code& error) {
    if (error || self->closed_) return;
    self->link_armed_for_ = -1;
    self->pump_links(steady_now_us());
  });
}

void GameSession::update(proto::TimeUs now) {
  if (closed_) return;
  client_.update(now);
  flush(now);
}

bool GameSession::send(std::span<const std::uint8_t> payload, proto::TimeUs now) {
  if (closed_) return false;
  const bool sent = client_.send_unreliable(payload, now);
  flush(now);
  return sent;
}

void GameSession::disconnect(proto::TimeUs now) {
  if (closed_) return;
  client_.disconnect(now);
  // The disconnect packets, straight out (a link would still hold them when the socket closes);
  // the event it queues is nobody's news.
  up_.reset();
  send_queued(now);
  abandon();
}

void GameSession::abandon() {
  if (closed_) return;
  // on_event_ stays (it may be the caller): closed_ stops every further event.
  closed_ = true;
  boost::system::error_code ignored;
  socket_.close(ignored);
  if (shared_port_) shared_port_->detach(shared_address_);
  link_timer_.cancel();
}

void GameSession::transmit(std::span<const std::uint8_t> bytes) {
  if (shared_port_) {
    if (!shared_port_->send(shared_address_, server_, bytes)) ++send_failures_;
    return;
  }
  boost::system::error_code error;
  socket_.send_to(asio::buffer(bytes.data(), bytes.size()), server_, 0, error);
  if (error) ++send_failures_;
}

void GameSession::send_queued(proto::TimeUs now) {
  while (!closed_ && client_.poll_transmit(outgoing_)) {
    if (up_) {
      up_->send(std::move(outgoing_.bytes), now);
    } else {
      transmit(outgoing_.bytes);  // copied out: the buffer goes back to the client next poll
    }
  }
}

void GameSession::flush(proto::TimeUs now) {
  send_queued(now);
  if (up_) pump_links(now);
  proto::ClientEvent event;
  while (!closed_ && client_.poll_event(event)) {
    if (on_event_) on_event_(event);
  }
}

}  // namespace ricochet::bot
