#include "game_channel.h"

#include <array>
#include <utility>

#include <boost/asio/as_tuple.hpp>
#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <spdlog/spdlog.h>

#include "ricochet/proto/packet.h"
#include "steady_time.h"

namespace ricochet::server {
namespace asio = boost::asio;
using asio::ip::udp;

namespace {

proto::Address to_address(const udp::endpoint& endpoint) {
  proto::Address address;
  address.port = endpoint.port();
  const asio::ip::address ip = endpoint.address();
  if (ip.is_v4()) {
    const auto bytes = ip.to_v4().to_bytes();
    std::copy(bytes.begin(), bytes.end(), address.ip.begin());
  } else {
    address.v6 = true;
    address.ip = ip.to_v6().to_bytes();
  }
  return address;
}

udp::endpoint to_endpoint(const proto::Address& address) {
  if (!address.v6) {
    asio::ip::address_v4::bytes_type bytes;
    std::copy_n(address.ip.begin(), bytes.size(), bytes.begin());
    return {asio::ip::address_v4(bytes), address.port};
  }
  return {asio::ip::address_v6(address.ip), address.port};
}

}  // namespace

GameChannel::GameChannel(asio::io_context& io, GameChannelConfig config)
    : config_(std::move(config)),
      strand_(asio::make_strand(io)),
      socket_(strand_),
      update_timer_(strand_),
      transport_(config_.transport) {}

GameChannel::~GameChannel() = default;

void GameChannel::start(GameRouter& router) {
  router_ = &router;
  const udp::endpoint endpoint(asio::ip::make_address(config_.bind), config_.port);
  socket_.open(endpoint.protocol());
  socket_.bind(endpoint);
  // A full send buffer must never stall the strand: send_to then fails with would_block and the
  // datagram is lost like any other (the protocol is built for loss).
  socket_.non_blocking(true);
  // Room for bursts (many clients' inputs at once, or a flood being dropped) while the strand
  // is busy: 4 MiB is some 3000 full datagrams. The kernel may cap it (net.core.rmem_max).
  boost::system::error_code ignored;
  socket_.set_option(asio::socket_base::receive_buffer_size(4 << 20), ignored);
  port_ = socket_.local_endpoint().port();
  asio::co_spawn(strand_, receive_loop(), asio::detached);
  asio::co_spawn(strand_, update_loop(), asio::detached);
}

void GameChannel::stop(std::function<void()> done) {
  asio::post(strand_, [this, done = std::move(done)] {
    if (!stopping_) {
      stopping_ = true;
      const proto::TimeUs now = steady_now_us();
      transport_.update(now);  // what the matches queued last (MatchEnded) goes out first
      drain();
      transport_.disconnect_all(proto::DisconnectReason::ServerShutdown, now);
      drain();
      publish_counters();
      boost::system::error_code ignored;
      update_timer_.cancel();
      socket_.close(ignored);
    }
    if (done) done();
  });
}

void GameChannel::send(std::uint64_t account, bool reliable, std::vector<std::uint8_t> bytes) {
  asio::post(strand_, [this, account, reliable, bytes = std::move(bytes)] {
    if (stopping_) return;
    const auto found = client_of_account_.find(account);
    if (found == client_of_account_.end()) return;
    const proto::TimeUs now = steady_now_us();
    if (reliable) {
      transport_.send_reliable(found->second, bytes, now);
    } else {
      transport_.send_unreliable(found->second, bytes, now);
    }
    drain();
  });
}

void GameChannel::kick(std::uint64_t account, proto::DisconnectReason reason) {
  asio::post(strand_, [this, account, reason] {
    const auto found = client_of_account_.find(account);
    if (found == client_of_account_.end()) return;
    const proto::ClientId client = found->second;
    const proto::TimeUs now = steady_now_us();
    transport_.update(now);  // what is queued for it goes out before the disconnect packets
    drain();
    if (transport_.connected(client)) transport_.disconnect(client, reason, now);
    drain();
  });
}

proto::TransportCounters GameChannel::counters() const {
  const std::lock_guard lock(counters_mutex_);
  return published_;
}

asio::awaitable<void> GameChannel::receive_loop() {
  std::array<std::uint8_t, proto::kMaxDatagramBytes + 1> buffer{};
  udp::endpoint from;
  while (!stopping_) {
    auto [error, size] = co_await socket_.async_receive_from(
        asio::buffer(buffer), from, asio::as_tuple(asio::use_awaitable));
    if (error == asio::error::operation_aborted || stopping_) break;
    if (error) {
      // ICMP port unreachable from a client that went away, and the like: not fatal.
      spdlog::debug("game channel: receive failed: {}", error.message());
      continue;
    }
    // A datagram larger than the buffer arrives truncated to kMaxDatagramBytes + 1 bytes, which
    // the transport drops as Oversized.
    transport_.receive(to_address(from), std::span(buffer.data(), size), steady_now_us());
    drain();
  }
}

asio::awaitable<void> GameChannel::update_loop() {
  while (!stopping_) {
    update_timer_.expires_after(std::chrono::microseconds(config_.update_interval_us));
    auto [error] = co_await update_timer_.async_wait(asio::as_tuple(asio::use_awaitable));
    if (error || stopping_) break;
    transport_.update(steady_now_us());
    drain();
    publish_counters();
  }
}

void GameChannel::drain() {
  proto::ServerEvent event;
  while (transport_.poll_event(event)) {
    if (auto* connected = std::get_if<proto::ServerConnected>(&event)) {
      client_of_account_[connected->account_id] = connected->client;
      account_of_client_[connected->client] = connected->account_id;
      router_->connected(connected->account_id, connected->match_id);
    } else if (auto* gone = std::get_if<proto::ServerDisconnected>(&event)) {
      account_of_client_.erase(gone->client);
      const auto found = client_of_account_.find(gone->account_id);
      // The transport reports a replaced connection's end before the new one's start, so the
      // match sees a disconnect and then a reconnect of the same account (keeping its entity).
      // Should a connection's end come after its successor's start, the account already names
      // the successor and the end is no news.
      if (found != client_of_account_.end() && found->second == gone->client) {
        client_of_account_.erase(found);
        router_->disconnected(gone->account_id, gone->reason);
      }
    } else if (auto* payload = std::get_if<proto::ServerUnreliable>(&event)) {
      const auto found = account_of_client_.find(payload->client);
      if (found != account_of_client_.end()) {
        router_->payload(found->second, std::move(payload->bytes),
                         transport_.rtt_us(payload->client));
      }
    } else if (auto* message = std::get_if<proto::ServerReliable>(&event)) {
      const auto found = account_of_client_.find(message->client);
      if (found != account_of_client_.end()) router_->reliable(found->second, std::move(message->bytes));
    }
  }
  proto::Transmit transmit;
  while (transport_.poll_transmit(transmit)) {
    if (!socket_.is_open()) continue;
    boost::system::error_code error;
    socket_.send_to(asio::buffer(transmit.bytes), to_endpoint(transmit.to), 0, error);
    if (error && error != asio::error::would_block) {
      spdlog::debug("game channel: send to {} failed: {}", transmit.to.to_string(), error.message());
    }
  }
}

void GameChannel::publish_counters() {
  const std::lock_guard lock(counters_mutex_);
  published_ = transport_.counters();
}

}  // namespace ricochet::server
