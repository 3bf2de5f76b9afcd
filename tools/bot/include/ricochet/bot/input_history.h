#pragma once
/// The inputs a bot sent on its current game connection that the server has not applied yet
/// (PROTOCOL.md ClientPayload: each input goes in several consecutive payloads, so one lost
/// packet loses none). ServerPayload.last_input_sequence acknowledges them. These are also the
/// inputs a client-side predictor replays on top of each snapshot's own state.

#include <cstddef>
#include <cstdint>
#include <deque>

#include "ricochet/wire/game.pb.h"

namespace ricochet::bot {

class InputHistory {
 public:
  /// Inputs kept unacknowledged at most; older ones are dropped (the server skips them too).
  static constexpr std::size_t kMaxKept = 64;
  /// Inputs repeated per payload (the protocol allows 8).
  static constexpr std::size_t kPerPayload = 4;

  /// Numbers `input` with the next sequence (1, 2, 3 ... per connection) and keeps it.
  const wire::Input& push(wire::Input input);
  /// From an untrusted payload: drops the inputs with sequence <= `sequence`. A sequence this
  /// connection never sent is ignored (returns false).
  bool acknowledge(std::uint32_t sequence);
  /// The newest kPerPayload inputs, oldest first, into `out`.
  void fill(wire::ClientPayload& out) const;

  const std::deque<wire::Input>& unacknowledged() const { return kept_; }
  std::uint32_t last_sequence() const { return next_sequence_ - 1; }
  std::uint32_t acknowledged() const { return acknowledged_; }

 private:
  std::deque<wire::Input> kept_;
  std::deque<wire::Input> recent_;  ///< the newest kPerPayload, acknowledged or not
  std::uint32_t next_sequence_ = 1;
  std::uint32_t acknowledged_ = 0;
};

}  // namespace ricochet::bot
