#pragma once
/// Datagrams in and out of one non-blocking UDP socket in batches (Linux recvmmsg/sendmmsg): one
/// system call for up to kDatagramBatch datagrams instead of one each. Under load the game
/// channel's socket has many inputs waiting at every wake-up, and a tick's snapshots leave
/// together.

#include <sys/socket.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "ricochet/proto/packet.h"
#include "ricochet/proto/transmit.h"

namespace ricochet::server {

inline constexpr std::size_t kDatagramBatch = 64;

/// The socket address of `address` (IPv4 or IPv6); its length in `length`.
sockaddr_storage to_sockaddr(const proto::Address& address, socklen_t& length);
/// The transport's view of a socket address (an unknown family reads as port 0).
proto::Address from_sockaddr(const sockaddr_storage& address);

class DatagramReceiver {
 public:
  DatagramReceiver();
  /// Reads the datagrams waiting on `fd` now (at most kDatagramBatch, never blocking); 0 when
  /// none, or on an error (then `error` says which). A datagram larger than kMaxDatagramBytes
  /// comes truncated to kMaxDatagramBytes + 1 bytes, for the transport to drop as oversized.
  std::size_t receive(int fd, std::string& error);
  std::span<const std::uint8_t> bytes(std::size_t i) const;
  proto::Address from(std::size_t i) const { return from_sockaddr(addresses_[i]); }

 private:
  std::vector<std::array<std::uint8_t, proto::kMaxDatagramBytes + 1>> buffers_;
  std::array<sockaddr_storage, kDatagramBatch> addresses_{};
  std::array<iovec, kDatagramBatch> iovecs_{};
  std::array<mmsghdr, kDatagramBatch> headers_{};
};

class DatagramSender {
 public:
  void add(proto::Transmit transmit) { queued_.push_back(std::move(transmit)); }
  std::size_t queued() const { return queued_.size(); }
  /// Sends everything queued on `fd` (never blocking) and empties the queue. A datagram the
  /// socket refuses (a full buffer) is lost like any other; returns how many were, with the
  /// first reason in `error`.
  std::size_t flush(int fd, std::string& error);
  /// Drops what is queued (the socket is closed).
  void discard() { queued_.clear(); }

 private:
  std::vector<proto::Transmit> queued_;
  std::vector<sockaddr_storage> addresses_;
  std::vector<iovec> iovecs_;
  std::vector<mmsghdr> headers_;
};

}  // namespace ricochet::server
