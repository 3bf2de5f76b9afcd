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

/// Queued datagrams live in slots that keep their buffers between flushes: filled by
/// GameServer::poll_transmit, which swaps a packet's buffer for the slot's old one, the steady
/// stream of snapshots allocates nothing.
class DatagramSender {
 public:
  /// The slot the next datagram goes into; queued by commit().
  proto::Transmit& next() {
    if (queued_ == slots_.size()) slots_.emplace_back();
    return slots_[queued_];
  }
  void commit() { ++queued_; }
  std::size_t queued() const { return queued_; }
  /// Sends everything queued on `fd` (never blocking) and empties the queue. A datagram the
  /// socket refuses (a full buffer) is lost like any other; returns how many were, with the
  /// first reason in `error`.
  std::size_t flush(int fd, std::string& error);
  /// Drops what is queued (the socket is closed).
  void discard() { queued_ = 0; }

 private:
  static constexpr std::size_t kSlotsKept = 4096;

  std::vector<proto::Transmit> slots_;
  std::size_t queued_ = 0;
  std::vector<sockaddr_storage> addresses_;
  std::vector<iovec> iovecs_;
  std::vector<mmsghdr> headers_;
};

}  // namespace ricochet::server
