#pragma once
/// One UDP socket carrying the game channels of many bots of a process (load tests). Each game
/// session sends from a loopback address of its own (127.1.0.1, 127.1.0.2, ...; IP_PKTINFO
/// picks the source of each datagram), so the server still sees one address per client, while
/// the process sends a loop turn's datagrams with one sendmmsg and reads arrivals 64 at a time
/// with recvmmsg, instead of one system call per datagram (and a readiness wake-up per socket).
/// On loopback the system calls are most of a datagram's cost: sendto + recv took 3.9 µs a
/// datagram against 1.05 µs for sendmmsg + recvmmsg in batches of 64 on our VMs.
///
/// Linux and IPv4 loopback only: the sessions' addresses exist on the loopback interface alone.

#include <sys/socket.h>

#include <array>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "ricochet/proto/packet.h"

namespace ricochet::bot {

class GameSession;

class SharedGamePort : public std::enable_shared_from_this<SharedGamePort> {
 public:
  /// Datagrams read or sent per system call.
  static constexpr std::size_t kBatch = 64;
  /// Bytes asked for each of the socket's buffers (the kernel may give less: net.core.*mem_max).
  static constexpr int kSocketBufferBytes = 8 << 20;

  /// Binds a socket to 0.0.0.0 on a free port; null with `error` set when it cannot.
  static std::shared_ptr<SharedGamePort> open(boost::asio::io_context& io, std::string& error);
  SharedGamePort(const SharedGamePort&) = delete;
  SharedGamePort& operator=(const SharedGamePort&) = delete;
  ~SharedGamePort();

  std::uint16_t port() const { return port_; }
  /// A fresh source address for `session` (never one handed out before, so a reconnect is a
  /// new client to the server); datagrams to it go to the session until detach(). nullopt when
  /// the addresses ran out.
  std::optional<boost::asio::ip::address_v4> attach(std::weak_ptr<GameSession> session);
  void detach(const boost::asio::ip::address_v4& local);
  /// Queues a datagram from `local` to `to` (IPv4); everything queued leaves together once the
  /// loop turn ends (a posted flush). Datagrams over kMaxDatagramBytes are refused (false).
  bool send(const boost::asio::ip::address_v4& local, const boost::asio::ip::udp::endpoint& to,
            std::span<const std::uint8_t> bytes);

  /// Datagrams the socket would not take (full buffer) or refused; they are lost.
  std::uint64_t send_failures() const { return send_failures_; }
  /// Datagrams that arrived for no attached session (one that closed), dropped.
  std::uint64_t unrouted() const { return unrouted_; }
  std::uint64_t send_calls() const { return send_calls_; }
  std::uint64_t receive_calls() const { return receive_calls_; }
  /// What the kernel gave the socket's receive buffer, bytes.
  int receive_buffer_bytes() const { return receive_buffer_bytes_; }

 private:
  SharedGamePort(boost::asio::io_context& io, int fd, std::uint16_t port);
  void wait_readable();
  void drain();
  void flush();

  struct Queued {
    std::uint32_t local = 0;  ///< host order
    sockaddr_in to{};
    std::uint32_t offset = 0;  ///< in queued_bytes_
    std::uint32_t size = 0;
  };

  boost::asio::io_context& io_;
  boost::asio::ip::udp::socket socket_;
  std::uint16_t port_ = 0;
  int receive_buffer_bytes_ = 0;
  std::uint32_t next_address_ = 0;  ///< offset of the next address from 127.1.0.0
  std::unordered_map<std::uint32_t, std::weak_ptr<GameSession>> sessions_;  ///< by address
  std::vector<Queued> queued_;
  std::vector<std::uint8_t> queued_bytes_;
  bool flush_posted_ = false;
  bool reading_ = false;
  std::uint64_t send_failures_ = 0, unrouted_ = 0, send_calls_ = 0, receive_calls_ = 0;
  /// recvmmsg's and sendmmsg's arrays.
  std::vector<std::array<std::uint8_t, proto::kMaxDatagramBytes + 1>> buffers_;
  std::vector<sockaddr_in> addresses_;
  std::vector<iovec> iovecs_;
  std::vector<mmsghdr> headers_;
  std::vector<std::array<std::uint8_t, 64>> controls_;  ///< one IP_PKTINFO cmsg each
};

}  // namespace ricochet::bot
