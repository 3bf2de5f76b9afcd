#include "datagram_batch.h"

#include <netinet/in.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace ricochet::server {

sockaddr_storage to_sockaddr(const proto::Address& address, socklen_t& length) {
  sockaddr_storage out{};
  if (!address.v6) {
    auto* v4 = reinterpret_cast<sockaddr_in*>(&out);
    v4->sin_family = AF_INET;
    v4->sin_port = htons(address.port);
    std::memcpy(&v4->sin_addr, address.ip.data(), 4);
    length = sizeof(sockaddr_in);
  } else {
    auto* v6 = reinterpret_cast<sockaddr_in6*>(&out);
    v6->sin6_family = AF_INET6;
    v6->sin6_port = htons(address.port);
    std::memcpy(&v6->sin6_addr, address.ip.data(), 16);
    length = sizeof(sockaddr_in6);
  }
  return out;
}

proto::Address from_sockaddr(const sockaddr_storage& address) {
  proto::Address out;
  if (address.ss_family == AF_INET) {
    const auto* v4 = reinterpret_cast<const sockaddr_in*>(&address);
    std::memcpy(out.ip.data(), &v4->sin_addr, 4);
    out.port = ntohs(v4->sin_port);
  } else if (address.ss_family == AF_INET6) {
    const auto* v6 = reinterpret_cast<const sockaddr_in6*>(&address);
    std::memcpy(out.ip.data(), &v6->sin6_addr, 16);
    out.port = ntohs(v6->sin6_port);
    out.v6 = true;
  }
  return out;
}

DatagramReceiver::DatagramReceiver() : buffers_(kDatagramBatch) {
  for (std::size_t i = 0; i < kDatagramBatch; ++i) {
    iovecs_[i] = {buffers_[i].data(), buffers_[i].size()};
  }
}

std::size_t DatagramReceiver::receive(int fd, std::string& error) {
  for (std::size_t i = 0; i < kDatagramBatch; ++i) {
    headers_[i] = {};
    headers_[i].msg_hdr.msg_name = &addresses_[i];
    headers_[i].msg_hdr.msg_namelen = sizeof(sockaddr_storage);
    headers_[i].msg_hdr.msg_iov = &iovecs_[i];
    headers_[i].msg_hdr.msg_iovlen = 1;
  }
  const int count = recvmmsg(fd, headers_.data(), kDatagramBatch, MSG_DONTWAIT, nullptr);
  if (count < 0) {
    if (errno != EAGAIN && errno != EWOULDBLOCK) error = std::strerror(errno);
    return 0;
  }
  return static_cast<std::size_t>(count);
}

std::span<const std::uint8_t> DatagramReceiver::bytes(std::size_t i) const {
  return {buffers_[i].data(), std::min<std::size_t>(headers_[i].msg_len, buffers_[i].size())};
}

std::size_t DatagramSender::flush(int fd, std::string& error) {
  const std::size_t count = queued_;
  addresses_.resize(count);
  iovecs_.resize(count);
  headers_.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    socklen_t length = 0;
    addresses_[i] = to_sockaddr(slots_[i].to, length);
    iovecs_[i] = {slots_[i].bytes.data(), slots_[i].bytes.size()};
    headers_[i] = {};
    headers_[i].msg_hdr.msg_name = &addresses_[i];
    headers_[i].msg_hdr.msg_namelen = length;
    headers_[i].msg_hdr.msg_iov = &iovecs_[i];
    headers_[i].msg_hdr.msg_iovlen = 1;
  }
  std::size_t lost = 0;
  std::size_t next = 0;
  while (next < count) {
    const auto batch = static_cast<unsigned>(std::min(kDatagramBatch, count - next));
    const int sent = sendmmsg(fd, headers_.data() + next, batch, MSG_DONTWAIT);
    if (sent > 0) {
      next += static_cast<std::size_t>(sent);
      continue;
    }
    // The datagram at `next` was refused (a full buffer, an unreachable address): it is lost.
    if (error.empty()) error = sent < 0 ? std::strerror(errno) : "not sent";
    ++lost;
    ++next;
  }
  queued_ = 0;
  // A burst larger than any steady stream (disconnect_all's copies) does not pin its memory.
  if (slots_.size() > kSlotsKept) slots_.resize(kSlotsKept);
  return lost;
}

}  // namespace ricochet::server
