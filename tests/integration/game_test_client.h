#pragma once
/// A game-channel client over a real UDP socket on 127.0.0.1: proto::GameClient (the sans-IO
/// client end) pumped through a non-blocking socket, with every event kept for the test.

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "ricochet/proto/game_client.h"
#include "ricochet/proto/token_grant.h"
#include "ricochet/wire/control.pb.h"

namespace ricochet::test {

class GameTestClient {
 public:
  /// Opens a socket on a free loopback port; connects with the join reply's token.
  GameTestClient(const wire::JoinMatchReply& join, std::uint16_t server_port)
      : socket_(io_, boost::asio::ip::udp::endpoint(boost::asio::ip::make_address("127.0.0.1"), 0)),
        server_(boost::asio::ip::make_address("127.0.0.1"), server_port) {
    socket_.non_blocking(true);
    proto::ClientConnectInfo info;
    info.grant.connect_token.assign(join.connect_token().begin(), join.connect_token().end());
    std::copy_n(join.client_to_server_key().begin(), proto::kKeyBytes,
                info.grant.client_to_server.begin());
    std::copy_n(join.server_to_client_key().begin(), proto::kKeyBytes,
                info.grant.server_to_client.begin());
    info.grant.timeout_s = join.timeout_s();
    info.protocol_id = proto::kProtocolId;
    info.server = proto::Address::ipv4(127, 0, 0, 1, server_port);
    client_ = std::make_unique<proto::GameClient>(std::move(info), now());
  }

  static proto::TimeUs now() {
    return std::chrono::duration_cast<std::chrono::microseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }

  /// Moves datagrams both ways and updates the client for `duration`, calling `each_ms` (if set)
  /// about every millisecond.
  template <class Each>
  void pump_for(std::chrono::milliseconds duration, Each each_ms) {
    const auto until = std::chrono::steady_clock::now() + duration;
    while (std::chrono::steady_clock::now() < until) {
      pump_once();
      each_ms();
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }
  void pump_for(std::chrono::milliseconds duration) {
    pump_for(duration, [] {});
  }
  /// Pumps until the state is `state` or `limit` passes; whether it got there.
  bool pump_until(proto::ConnectionState state, std::chrono::milliseconds limit) {
    const auto until = std::chrono::steady_clock::now() + limit;
    while (client_->state() != state && std::chrono::steady_clock::now() < until) {
      pump_once();
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return client_->state() == state;
  }

  void send(const std::string& bytes) {
    client_->send_unreliable(
        std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()), now());
    flush();
  }
  /// Raw bytes straight onto the socket (hostile-client tests).
  void send_raw(const std::vector<std::uint8_t>& bytes) {
    boost::system::error_code ignored;
    socket_.send_to(boost::asio::buffer(bytes), server_, 0, ignored);
  }

  proto::GameClient& transport() { return *client_; }
  std::vector<proto::ClientEvent>& events() { return events_; }

 private:
  void pump_once() {
    std::array<std::uint8_t, 1500> buffer{};
    boost::asio::ip::udp::endpoint from;
    boost::system::error_code error;
    for (;;) {
      const std::size_t size = socket_.receive_from(boost::asio::buffer(buffer), from, 0, error);
      if (error) break;
      client_->receive(proto::Address::ipv4(127, 0, 0, 1, from.port()),
                       std::span(buffer.data(), size), now());
    }
    client_->update(now());
    flush();
  }
  void flush() {
    proto::Transmit transmit;
    while (client_->poll_transmit(transmit)) {
      boost::system::error_code ignored;
      socket_.send_to(boost::asio::buffer(transmit.bytes), server_, 0, ignored);
    }
    proto::ClientEvent event;
    while (client_->poll_event(event)) events_.push_back(std::move(event));
  }

  boost::asio::io_context io_;
  boost::asio::ip::udp::socket socket_;
  boost::asio::ip::udp::endpoint server_;
  std::unique_ptr<proto::GameClient> client_;
  std::vector<proto::ClientEvent> events_;
};

}  // namespace ricochet::test
