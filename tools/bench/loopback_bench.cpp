/// Loopback bench: what a datagram costs through the kernel on this machine now, the work that
/// dominates the capacity benchmark's server core (tools/bench/CAPACITY.md: UDP and epoll, the
/// AEAD, memcpy) and that match-bench's calibration does not time. Two threads on two cores
/// (--cores, capacity.sh's 0 and 1), one UDP socket each on 127.0.0.1:
///   server: seals --batch snapshot-sized game packets (proto's packet codec: ChaCha20-Poly1305,
///           as the game channel sends them), sends them in sendmmsg batches of 64 (the server's
///           kDatagramBatch), then waits in epoll and takes the client's answers with recvmmsg,
///           opening each;
///   client: the same in reverse, an input-sized packet back for each snapshot it opened.
/// One round is one batch there and back. Per round: the server thread's CPU time (its
/// syscalls and the loopback delivery they run included) and the round's wall time, each divided
/// by the batch: µs per datagram out and its answer in. A round with a datagram lost (none on an
/// idle loopback) is counted and not sampled.
///
///   loopback-bench [--seconds 3] [--batch 64] [--snapshot-bytes 140] [--input-bytes 120]
///                  [--cores 0,1] [--out FILE]
///
/// The default sizes are the capacity benchmark's datagrams at 1000 bots on 2026-12-06
/// (kbps_in_per_client 67.8 and kbps_out_per_client 58.3 at 60 Hz: 141 and 121 bytes).

#include <netinet/in.h>
#include <pthread.h>
#include <sched.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <span>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "harness.h"
#include "ricochet/proto/packet.h"

namespace proto = ricochet::proto;
namespace bench = ricochet::bench;

namespace {

constexpr std::size_t kSyscallBatch = 64;  ///< datagrams per sendmmsg/recvmmsg, as the server's
constexpr std::uint64_t kProtocolId = 0x5249434f43484554;
constexpr int kWaitMs = 100;  ///< a round whose answers have not all come by then lost some
constexpr std::size_t kPacketOverhead = proto::kEncryptedHeaderBytes + proto::kMacBytes;

struct BenchOptions {
  double seconds = 3;
  std::size_t batch = 64;
  std::size_t snapshot_bytes = 140;  ///< whole datagram: header, body, tag
  std::size_t input_bytes = 120;
  std::vector<int> cores{0, 1};
};

proto::Key key_of(std::uint8_t seed) {
  proto::Key key{};
  for (std::size_t i = 0; i < key.size(); ++i) key[i] = static_cast<std::uint8_t>(seed ^ i);
  return key;
}

/// One end: a non-blocking UDP socket on 127.0.0.1 with its epoll, sealing its packets with
/// `send_key` and opening the other end's with `receive_key`.
class End {
 public:
  End(proto::Key send_key, proto::Key receive_key)
      : send_key_(send_key), receive_key_(receive_key) {
    fd_ = socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t length = sizeof address;
    if (fd_ < 0 || bind(fd_, reinterpret_cast<sockaddr*>(&address), length) != 0 ||
        getsockname(fd_, reinterpret_cast<sockaddr*>(&address), &length) != 0)
      throw std::runtime_error(std::string("loopback socket: ") + std::strerror(errno));
    address_ = address;
    epoll_ = epoll_create1(EPOLL_CLOEXEC);
    epoll_event event{};
    event.events = EPOLLIN;
    if (epoll_ < 0 || epoll_ctl(epoll_, EPOLL_CTL_ADD, fd_, &event) != 0)
      throw std::runtime_error(std::string("epoll: ") + std::strerror(errno));
    for (auto& buffer : in_) buffer.resize(proto::kMaxDatagramBytes);
  }
  ~End() {
    close(epoll_);
    close(fd_);
  }
  End(const End&) = delete;
  End& operator=(const End&) = delete;

  const sockaddr_in& address() const { return address_; }

  /// Seals `count` packets of `bytes` and sends them to `to`, kSyscallBatch per sendmmsg.
  void send(std::size_t count, std::size_t bytes, const sockaddr_in& to) {
    while (out_.size() < count) out_.emplace_back();
    body_out_.assign(bytes - kPacketOverhead, 0x42);
    for (std::size_t i = 0; i < count; ++i) {
      proto::begin_packet(proto::PacketType::Payload, ++sequence_, out_[i]);
      out_[i].insert(out_[i].end(), body_out_.begin(), body_out_.end());
      proto::seal_packet_in_place(kProtocolId, send_key_, out_[i]);
    }
    for (std::size_t first = 0; first < count; first += kSyscallBatch) {
      const std::size_t n = std::min(kSyscallBatch, count - first);
      std::array<iovec, kSyscallBatch> iovecs{};
      std::array<mmsghdr, kSyscallBatch> headers{};
      for (std::size_t i = 0; i < n; ++i) {
        iovecs[i] = {out_[first + i].data(), out_[first + i].size()};
        headers[i].msg_hdr.msg_name = const_cast<sockaddr_in*>(&to);
        headers[i].msg_hdr.msg_namelen = sizeof to;
        headers[i].msg_hdr.msg_iov = &iovecs[i];
        headers[i].msg_hdr.msg_iovlen = 1;
      }
      // A datagram the socket refuses is lost, as the server's are: the round is not sampled.
      sendmmsg(fd_, headers.data(), static_cast<unsigned>(n), 0);
    }
  }

  /// Waits up to kWaitMs for datagrams and opens what came (recvmmsg, kSyscallBatch at a time,
  /// until none wait); how many opened. 0 after the wait with nothing.
  std::size_t receive() {
    epoll_event event{};
    if (epoll_wait(epoll_, &event, 1, kWaitMs) <= 0) return 0;
    std::size_t opened = 0;
    for (;;) {
      std::array<iovec, kSyscallBatch> iovecs{};
      std::array<mmsghdr, kSyscallBatch> headers{};
      for (std::size_t i = 0; i < kSyscallBatch; ++i) {
        iovecs[i] = {in_[i].data(), in_[i].size()};
        headers[i].msg_hdr.msg_iov = &iovecs[i];
        headers[i].msg_hdr.msg_iovlen = 1;
      }
      const int n = recvmmsg(fd_, headers.data(), kSyscallBatch, MSG_DONTWAIT, nullptr);
      if (n <= 0) return opened;
      for (int i = 0; i < n; ++i) {
        const std::span<const std::uint8_t> datagram(in_[static_cast<std::size_t>(i)].data(),
                                                     headers[static_cast<std::size_t>(i)].msg_len);
        if (proto::read_encrypted_header(datagram).ok() &&
            proto::open_packet(datagram, kProtocolId, receive_key_, body_))
          ++opened;
      }
    }
  }

 private:
  int fd_ = -1;
  int epoll_ = -1;
  sockaddr_in address_{};
  proto::Key send_key_;
  proto::Key receive_key_;
  std::uint64_t sequence_ = 0;
  std::vector<std::vector<std::uint8_t>> out_;  ///< sealed packets, their buffers kept
  std::vector<std::uint8_t> body_out_;
  std::array<std::vector<std::uint8_t>, kSyscallBatch> in_;
  std::vector<std::uint8_t> body_;  ///< the last packet opened
};

bool pin_to(pthread_t thread, int core) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(core, &set);
  return pthread_setaffinity_np(thread, sizeof set, &set) == 0;
}

struct Result {
  std::vector<double> cpu_us;   ///< per datagram, one sample a round
  std::vector<double> wall_us;  ///< per datagram, one sample a round
  std::uint64_t rounds_lost = 0;
};

Result run(const BenchOptions& options) {
  End server(key_of(0x11), key_of(0x22));
  End client(key_of(0x22), key_of(0x11));
  std::atomic<bool> stop{false};
  std::thread answering([&] {
    while (!stop.load(std::memory_order_relaxed)) {
      const std::size_t opened = client.receive();
      if (opened > 0) client.send(opened, options.input_bytes, server.address());
    }
  });
  Result result;
  if (!pin_to(pthread_self(), options.cores[0]) ||
      !pin_to(answering.native_handle(), options.cores[1])) {
    stop = true;
    answering.join();
    throw std::runtime_error("cannot pin the two threads to cores " +
                             std::to_string(options.cores[0]) + " and " +
                             std::to_string(options.cores[1]));
  }
  const auto batch = static_cast<double>(options.batch);
  bench::Stopwatch total;
  while (total.elapsed_s() < options.seconds) {
    const std::int64_t cpu_start = bench::thread_cpu_ns();
    bench::Stopwatch round;
    server.send(options.batch, options.snapshot_bytes, client.address());
    std::size_t answers = 0;
    while (answers < options.batch) {
      const std::size_t opened = server.receive();
      if (opened == 0) break;
      answers += opened;
    }
    if (answers < options.batch) {
      ++result.rounds_lost;
      continue;
    }
    result.wall_us.push_back(round.elapsed_us() / batch);
    result.cpu_us.push_back(static_cast<double>(bench::thread_cpu_ns() - cpu_start) / 1e3 / batch);
  }
  stop = true;
  answering.join();
  return result;
}

}  // namespace

int main(int argc, char** argv) {
  BenchOptions options;
  std::string out;
  CLI::App app{"loopback-bench: a game datagram's cost through the kernel, core to core"};
  app.add_option("--seconds", options.seconds, "how long to run")
      ->check(CLI::Range(0.1, 600.0))
      ->capture_default_str();
  app.add_option("--batch", options.batch, "snapshots per round, each answered by an input")
      ->check(CLI::Range(1, 1024))
      ->capture_default_str();
  app.add_option("--snapshot-bytes", options.snapshot_bytes,
                 "each snapshot datagram, header and tag included, bytes")
      ->check(CLI::Range(kPacketOverhead + 1, proto::kMaxDatagramBytes))
      ->capture_default_str();
  app.add_option("--input-bytes", options.input_bytes,
                 "each input datagram, header and tag included, bytes")
      ->check(CLI::Range(kPacketOverhead + 1, proto::kMaxDatagramBytes))
      ->capture_default_str();
  app.add_option("--cores", options.cores, "the server's core and the client's")
      ->delimiter(',')
      ->expected(2)
      ->check(CLI::Range(0, CPU_SETSIZE - 1));
  app.add_option("--out", out, "also append the JSON line to this file");
  CLI11_PARSE(app, argc, argv);

  bench::ResultsOut results(out);
  if (!results.ok()) {
    std::fprintf(stderr, "loopback-bench: cannot write %s\n", out.c_str());
    return 2;
  }
  Result result;
  try {
    result = run(options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "loopback-bench: %s\n", e.what());
    return 1;
  }
  if (result.cpu_us.empty()) {
    std::fprintf(stderr, "loopback-bench: every round lost datagrams (%llu rounds)\n",
                 static_cast<unsigned long long>(result.rounds_lost));
    return 1;
  }
  const ricochet::stats::Summary cpu = ricochet::stats::summarize(result.cpu_us);
  const ricochet::stats::Summary wall = ricochet::stats::summarize(result.wall_us);
  results.write(bench::result_line("loopback")
                    .integer("batch", options.batch)
                    .integer("snapshot_bytes", options.snapshot_bytes)
                    .integer("input_bytes", options.input_bytes)
                    .integer("server_core", options.cores[0])
                    .integer("client_core", options.cores[1])
                    .integer("rounds", cpu.count)
                    .integer("rounds_lost", result.rounds_lost)
                    .number("cpu_us_per_datagram_p50", cpu.p50, 3)
                    .number("cpu_us_per_datagram_p99", cpu.p99, 3)
                    .number("cpu_us_per_datagram_avg", cpu.mean, 3)
                    .number("wall_us_per_datagram_p50", wall.p50, 3)
                    .number("wall_us_per_datagram_p99", wall.p99, 3));
  return 0;
}
