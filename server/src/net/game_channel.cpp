#include "game_channel.h"

#include <netinet/in.h>
#include <spdlog/spdlog.h>
#include <sys/socket.h>

#include <boost/asio/as_tuple.hpp>
#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <utility>

#include "ricochet/proto/packet.h"
#include "steady_time.h"

namespace ricochet::server {
namespace asio = boost::asio;
using asio::ip::udp;

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
  // Datagrams leave with Don't Fragment set and are never fragmented here (they are at most
  // kMaxDatagramBytes, under any path's MTU), as QUIC stacks send theirs. With it Linux also
  // stamps IPv4 packets with ID 0 instead of hashing a fresh ID for each one.
  const int probe = endpoint.address().is_v4() ? IP_PMTUDISC_PROBE : IPV6_PMTUDISC_PROBE;
  setsockopt(socket_.native_handle(), endpoint.address().is_v4() ? IPPROTO_IP : IPPROTO_IPV6,
             endpoint.address().is_v4() ? IP_MTU_DISCOVER : IPV6_MTU_DISCOVER, &probe,
             sizeof probe);
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
  std::vector<Outgoing> one;
  one.push_back({account, reliable, std::move(bytes)});
  send_all(std::move(one));
}

void GameChannel::send_all(std::vector<Outgoing> messages) {
  asio::post(strand_, [this, messages = std::move(messages)] {
    if (stopping_) return;
    const proto::TimeUs now = steady_now_us();
    for (const Outgoing& message : messages) {
      const auto found = client_of_account_.find(message.account);
      if (found == client_of_account_.end()) continue;
      if (message.reliable) {
        transport_.send_reliable(found->second, message.bytes, now, message.delivery);
      } else {
        transport_.send_unreliable(found->second, message.bytes, now);
      }
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
  while (!stopping_) {
    auto [error] =
        co_await socket_.async_wait(udp::socket::wait_read, asio::as_tuple(asio::use_awaitable));
    if (error == asio::error::operation_aborted || stopping_) break;
    if (error) {
      spdlog::debug("game channel: waiting for datagrams failed: {}", error.message());
      continue;
    }
    receive_waiting();
    drain();
  }
}

void GameChannel::receive_waiting() {
  // At most 16 batches (1024 datagrams) per wake-up, so a flood cannot hold the strand.
  for (int batch = 0; batch < 16 && !stopping_; ++batch) {
    std::string error;
    const std::size_t count = receiver_.receive(socket_.native_handle(), error);
    if (!error.empty()) {
      // ICMP port unreachable from a client that went away, and the like: not fatal.
      spdlog::debug("game channel: receive failed: {}", error);
    }
    const proto::TimeUs now = steady_now_us();
    for (std::size_t i = 0; i < count; ++i) {
      transport_.receive(receiver_.from(i), receiver_.bytes(i), now);
    }
    if (count < kDatagramBatch) break;
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
  // Payloads are handed on together, but never after an event that came after them.
  std::vector<GamePayload> payloads;
  const auto route_payloads = [&] {
    if (!payloads.empty()) router_->payloads(std::exchange(payloads, {}));
  };
  proto::ServerEvent event;
  while (transport_.poll_event(event)) {
    if (!std::holds_alternative<proto::ServerUnreliable>(event)) route_payloads();
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
      // Only a connected client's payloads come, after its ServerConnected and before its end.
      payloads.push_back({payload->account_id, std::move(payload->bytes), payload->rtt_us});
    } else if (auto* message = std::get_if<proto::ServerReliable>(&event)) {
      const auto found = account_of_client_.find(message->client);
      if (found != account_of_client_.end())
        router_->reliable(found->second, std::move(message->bytes));
    }
  }
  route_payloads();
  while (transport_.poll_transmit(sender_.next())) sender_.commit();
  if (!socket_.is_open()) return sender_.discard();
  std::string error;
  if (const std::size_t lost = sender_.flush(socket_.native_handle(), error); lost > 0) {
    spdlog::debug("game channel: {} datagrams not sent: {}", lost, error);
  }
}

void GameChannel::publish_counters() {
  const std::lock_guard lock(counters_mutex_);
  published_ = transport_.counters();
}

}  // namespace ricochet::server
