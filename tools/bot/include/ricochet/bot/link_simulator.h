#pragma once
/// A bad network link in one direction, sans-IO (as netcode.io's and yojimbo's network
/// simulators): datagrams go in with the time they were sent and come out when due, after a
/// latency with uniform jitter, some lost, some duplicated, some held back so that later ones
/// overtake them. Seeded: the same seed and the same sends at the same times give the same
/// deliveries. The bot puts one on each direction of its game channel (game_session.h), so a
/// test can give one bot a bad mobile link without touching the machine's network.

#include <cstdint>
#include <optional>
#include <queue>
#include <random>
#include <string>
#include <vector>

#include "ricochet/proto/clock.h"

namespace ricochet::bot {

struct LinkConfig {
  double latency_ms = 0;  ///< one way, 0..5000
  double jitter_ms = 0;   ///< each datagram's delay is latency ± up to this (uniform), 0..latency
  double loss = 0;        ///< 0..1: probability a datagram is dropped
  double duplicate = 0;   ///< 0..1: probability a datagram is delivered twice (two delays)
  /// 0..1: probability a datagram is held back a further max(20 ms, 2 × jitter), so that the
  /// ones sent after it arrive first.
  double reorder = 0;

  /// False when the link is perfect (then nothing is simulated at all).
  bool active() const {
    return latency_ms > 0 || jitter_ms > 0 || loss > 0 || duplicate > 0 || reorder > 0;
  }
  /// Empty when usable; otherwise the first wrong field, its range and its value.
  std::string validate() const;
};

struct LinkCounters {
  std::uint64_t sent = 0;        ///< datagrams put in
  std::uint64_t dropped = 0;     ///< lost
  std::uint64_t duplicated = 0;  ///< extra copies made
  std::uint64_t reordered = 0;   ///< held back
  std::uint64_t delivered = 0;   ///< taken out (copies included)
};

class LinkSimulator {
 public:
  /// config must be valid.
  LinkSimulator(const LinkConfig& config, std::uint64_t seed);

  /// A datagram enters the link at `now`.
  void send(std::vector<std::uint8_t> datagram, proto::TimeUs now);
  /// The next datagram due by `now`, in order of due time (ties: in order sent); false when
  /// none is due.
  bool poll(proto::TimeUs now, std::vector<std::uint8_t>& out);
  /// When the next datagram is due; nullopt when none is in flight.
  std::optional<proto::TimeUs> next_due() const;

  const LinkCounters& counters() const { return counters_; }
  std::size_t in_flight() const { return queue_.size(); }

 private:
  struct InFlight {
    proto::TimeUs due = 0;
    std::uint64_t order = 0;
    std::vector<std::uint8_t> bytes;
    bool operator>(const InFlight& other) const {
      return due != other.due ? due > other.due : order > other.order;
    }
  };
  proto::TimeUs delay_us();

  LinkConfig config_;
  std::mt19937_64 random_;
  std::priority_queue<InFlight, std::vector<InFlight>, std::greater<>> queue_;
  std::uint64_t next_order_ = 0;
  LinkCounters counters_;
};

}  // namespace ricochet::bot
