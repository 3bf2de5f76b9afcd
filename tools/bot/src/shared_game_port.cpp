#include "ricochet/bot/shared_game_port.h"

#include <netinet/in.h>
#include <spdlog/spdlog.h>

#include <boost/asio/post.hpp>
#include <cerrno>
#include <cstring>

#include "ricochet/bot/game_session.h"

namespace ricochet::bot {

namespace asio = boost::asio;

namespace {

/// Session addresses: 127.1.0.1 onwards (the control channels use 127.0.x.y).
constexpr std::uint32_t kFirstAddress = 0x7F010000;
constexpr std::uint32_t kAddressCount = 0x00FEFFFF;  ///< up to 127.255.255.255

int set_buffer(int fd, int option, int force_option, int bytes) {
  // As root the FORCE variant passes net.core.*mem_max; otherwise the plain one, capped.
  if (setsockopt(fd, SOL_SOCKET, force_option, &bytes, sizeof bytes) != 0) {
    setsockopt(fd, SOL_SOCKET, option, &bytes, sizeof bytes);
  }
  int got = 0;
  socklen_t length = sizeof got;
  getsockopt(fd, SOL_SOCKET, option, &got, &length);
  return got;
}

}  // namespace

std::shared_ptr<SharedGamePort> SharedGamePort::open(asio::io_context& io, std::string& error) {
  const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) {
    error = std::string("cannot make a UDP socket: ") + std::strerror(errno);
    return nullptr;
  }
  const int on = 1;
  // Don't Fragment, and IPv4 ID 0 rather than a hashed ID per packet (game_channel.cpp).
  const int probe = IP_PMTUDISC_PROBE;
  setsockopt(fd, IPPROTO_IP, IP_MTU_DISCOVER, &probe, sizeof probe);
  sockaddr_in any{};
  any.sin_family = AF_INET;
  socklen_t length = sizeof any;
  if (setsockopt(fd, IPPROTO_IP, IP_PKTINFO, &on, sizeof on) != 0 ||
      ::bind(fd, reinterpret_cast<const sockaddr*>(&any), sizeof any) != 0 ||
      getsockname(fd, reinterpret_cast<sockaddr*>(&any), &length) != 0) {
    error = std::string("cannot bind the shared game socket: ") + std::strerror(errno);
    ::close(fd);
    return nullptr;
  }
  std::shared_ptr<SharedGamePort> port(new SharedGamePort(io, fd, ntohs(any.sin_port)));
  set_buffer(fd, SO_SNDBUF, SO_SNDBUFFORCE, kSocketBufferBytes);
  port->receive_buffer_bytes_ = set_buffer(fd, SO_RCVBUF, SO_RCVBUFFORCE, kSocketBufferBytes);
  return port;
}

SharedGamePort::SharedGamePort(asio::io_context& io, int fd, std::uint16_t port)
    : io_(io),
      socket_(io, asio::ip::udp::v4(), fd),
      port_(port),
      buffers_(kBatch),
      addresses_(kBatch),
      iovecs_(kBatch),
      headers_(kBatch),
      controls_(kBatch) {}

SharedGamePort::~SharedGamePort() {
  boost::system::error_code ignored;
  socket_.close(ignored);
}

std::optional<asio::ip::address_v4> SharedGamePort::attach(std::weak_ptr<GameSession> session) {
  if (next_address_ >= kAddressCount) return std::nullopt;
  const std::uint32_t address = kFirstAddress + ++next_address_;
  sessions_[address] = std::move(session);
  if (!reading_) {
    reading_ = true;
    wait_readable();
  }
  return asio::ip::address_v4(address);
}

void SharedGamePort::detach(const asio::ip::address_v4& local) {
  sessions_.erase(local.to_uint());
}

bool SharedGamePort::send(const asio::ip::address_v4& local, const asio::ip::udp::endpoint& to,
                          std::span<const std::uint8_t> bytes) {
  if (bytes.size() > proto::kMaxDatagramBytes || !to.address().is_v4()) {
    ++send_failures_;
    return false;
  }
  Queued queued;
  queued.local = local.to_uint();
  queued.to.sin_family = AF_INET;
  queued.to.sin_port = htons(to.port());
  queued.to.sin_addr.s_addr = htonl(to.address().to_v4().to_uint());
  queued.offset = static_cast<std::uint32_t>(queued_bytes_.size());
  queued.size = static_cast<std::uint32_t>(bytes.size());
  queued_bytes_.insert(queued_bytes_.end(), bytes.begin(), bytes.end());
  queued_.push_back(queued);
  if (!flush_posted_) {
    flush_posted_ = true;
    asio::post(io_, [weak = weak_from_this()] {
      if (auto self = weak.lock()) self->flush();
    });
  }
  return true;
}

void SharedGamePort::flush() {
  flush_posted_ = false;
  const int fd = socket_.native_handle();
  for (std::size_t first = 0; first < queued_.size(); first += kBatch) {
    const std::size_t count = std::min(kBatch, queued_.size() - first);
    for (std::size_t k = 0; k < count; ++k) {
      Queued& queued = queued_[first + k];
      iovecs_[k] = {queued_bytes_.data() + queued.offset, queued.size};
      msghdr& header = headers_[k].msg_hdr;
      header = {};
      header.msg_name = &queued.to;
      header.msg_namelen = sizeof queued.to;
      header.msg_iov = &iovecs_[k];
      header.msg_iovlen = 1;
      header.msg_control = controls_[k].data();
      header.msg_controllen = CMSG_SPACE(sizeof(in_pktinfo));
      cmsghdr* control = CMSG_FIRSTHDR(&header);
      control->cmsg_level = IPPROTO_IP;
      control->cmsg_type = IP_PKTINFO;
      control->cmsg_len = CMSG_LEN(sizeof(in_pktinfo));
      in_pktinfo info{};
      info.ipi_spec_dst.s_addr = htonl(queued.local);
      std::memcpy(CMSG_DATA(control), &info, sizeof info);
    }
    std::size_t sent = 0;
    while (sent < count) {
      ++send_calls_;
      const int result =
          ::sendmmsg(fd, headers_.data() + sent, static_cast<unsigned>(count - sent), 0);
      if (result > 0) {
        sent += static_cast<std::size_t>(result);
        continue;
      }
      if (result < 0 && errno == EINTR) continue;
      // A full buffer or an error for this datagram: it is lost like any other; go on.
      if (result < 0 && errno != EAGAIN && errno != EWOULDBLOCK) {
        spdlog::debug("shared game socket: sendmmsg: {}", std::strerror(errno));
      }
      ++send_failures_;
      ++sent;
    }
  }
  queued_.clear();
  queued_bytes_.clear();
}

void SharedGamePort::wait_readable() {
  socket_.async_wait(asio::ip::udp::socket::wait_read,
                     [weak = weak_from_this()](const boost::system::error_code& error) {
                       auto self = weak.lock();
                       if (!self || error) return;
                       self->drain();
                       self->wait_readable();
                     });
}

void SharedGamePort::drain() {
  const int fd = socket_.native_handle();
  for (int round = 0; round < 16; ++round) {  // at most 1024 datagrams, then other handlers
    for (std::size_t k = 0; k < kBatch; ++k) {
      iovecs_[k] = {buffers_[k].data(), buffers_[k].size()};
      msghdr& header = headers_[k].msg_hdr;
      header = {};
      header.msg_name = &addresses_[k];
      header.msg_namelen = sizeof addresses_[k];
      header.msg_iov = &iovecs_[k];
      header.msg_iovlen = 1;
      header.msg_control = controls_[k].data();
      header.msg_controllen = controls_[k].size();
    }
    ++receive_calls_;
    const int count = ::recvmmsg(fd, headers_.data(), kBatch, MSG_DONTWAIT, nullptr);
    if (count <= 0) return;
    const proto::TimeUs now = steady_now_us();
    for (int k = 0; k < count; ++k) {
      msghdr& header = headers_[k].msg_hdr;
      std::optional<std::uint32_t> local;
      for (cmsghdr* control = CMSG_FIRSTHDR(&header); control;
           control = CMSG_NXTHDR(&header, control)) {
        if (control->cmsg_level == IPPROTO_IP && control->cmsg_type == IP_PKTINFO) {
          in_pktinfo info{};
          std::memcpy(&info, CMSG_DATA(control), sizeof info);
          local = ntohl(info.ipi_addr.s_addr);
        }
      }
      const auto it = local ? sessions_.find(*local) : sessions_.end();
      std::shared_ptr<GameSession> session = it == sessions_.end() ? nullptr : it->second.lock();
      if (!session) {
        ++unrouted_;
        continue;
      }
      const sockaddr_in& from = addresses_[k];
      const asio::ip::udp::endpoint endpoint(asio::ip::address_v4(ntohl(from.sin_addr.s_addr)),
                                             ntohs(from.sin_port));
      // A datagram longer than the buffer comes cut (MSG_TRUNC): the transport drops it.
      session->receive_datagram(
          endpoint, std::span<const std::uint8_t>(buffers_[k].data(), headers_[k].msg_len), now);
    }
    if (static_cast<std::size_t>(count) < kBatch) return;
  }
}

}  // namespace ricochet::bot
