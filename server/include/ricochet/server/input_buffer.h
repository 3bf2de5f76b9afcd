#pragma once
/// A client's inputs on their way into the tick: validation of the untrusted wire values and a
/// small jitter buffer that hands the match exactly one input per tick.
///
/// Clients send one input per client tick and repeat the last few in every packet, so the
/// buffer sees most inputs several times and some out of order. It keeps the inputs newer than
/// the last applied one, sorted by sequence, and each tick applies the oldest of them. When none
/// has arrived it repeats the last applied input (the sequence echoed to the client does not
/// move, so the client knows it was not applied). When a burst arrives after a stall the buffer
/// holds at most max_depth inputs and skips the oldest, so the delay does not grow.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "ricochet/proto/input_wire.h"
#include "ricochet/wire/game.pb.h"

namespace ricochet::server {

/// Largest |pitch| validate_input() accepts, rad: the wire's π/2 with room for float rounding.
inline constexpr float kAcceptedMaxPitchRad = proto::kMaxPitchRad + 1e-6f;

/// One validated input (the wire values and their ranges are proto/input_wire.h's).
struct PlayerInput {
  std::uint32_t sequence = 0;      ///< 0 only for the neutral input before the first one arrives
  float move_right = 0;            ///< -1..1, with move_forward a vector of length <= 1
  float move_forward = 0;          ///< -1..1 (proto::stick_of of the wire's move steps)
  float yaw_rad = 0;               ///< -2π..2π, about +Y, 0 looks along -Z
  float pitch_rad = 0;             ///< -π/2..π/2, positive looks up
  std::uint32_t buttons = 0;       ///< proto::Button bits
  std::uint32_t weapon_slot = 0;   ///< 0 keeps the weapon, 1..9 select one
  std::uint32_t view_tick = 0;     ///< the server tick the client showed (0: not given)
  std::uint8_t view_fraction = 0;  ///< 1/256 of a tick past view_tick (proto::view_fraction_ticks)
  bool pressed(proto::Button button) const { return (buttons & button) != 0; }
};

/// Why an input (or a whole ClientPayload) was not used.
enum class InputDrop : std::uint8_t {
  MalformedPayload,  ///< bytes that are not a ClientPayload, or larger than a datagram
  TooManyInputs,     ///< more than proto::kMaxInputsPerPayload inputs: the whole payload is dropped
  NonFinite,         ///< NaN or infinite yaw or pitch
  OutOfRange,        ///< a move component, angle, button bit or weapon slot out of range
  ZeroSequence,      ///< sequence 0
  Stale,             ///< already applied or already buffered (the redundancy; expected)
  TooFarAhead,       ///< more than 1024 ahead of the last applied input
  Skipped,           ///< arrived in time but pushed out by newer ones after a stall
  UnknownPlayer,     ///< a payload for an account that is not connected to the match
};
inline constexpr std::size_t kInputDropCount =
    static_cast<std::size_t>(InputDrop::UnknownPlayer) + 1;
const char* name(InputDrop reason);

using InputDropCounters = std::array<std::uint64_t, kInputDropCount>;

/// Checks one wire input. Returns true and fills `out`, or returns false and sets `reason`
/// (NonFinite, OutOfRange or ZeroSequence).
bool validate_input(const wire::Input& in, PlayerInput& out, InputDrop& reason);

struct InputBufferConfig {
  std::size_t max_depth = 4;  ///< inputs kept ahead of the tick, 1..32

  std::string validate() const;
};

class InputBuffer {
 public:
  explicit InputBuffer(const InputBufferConfig& config = {});

  /// Offers a validated input; counts it in `drops` when it is not kept.
  void offer(const PlayerInput& input, InputDropCounters& drops);
  /// The input for this tick: the oldest buffered one, or the last applied one again.
  /// `repeated` tells which.
  const PlayerInput& next(bool& repeated);

  /// Sequence of the last input applied (0: none yet): echoed in ServerPayload.
  std::uint32_t last_applied_sequence() const { return last_.sequence; }
  /// Neither applied nor waiting: offer() would not count it as stale.
  bool is_new(std::uint32_t sequence) const;
  std::size_t buffered() const { return pending_.size(); }
  /// Forgets everything: a reconnected client restarts its sequence at 1.
  void reset();

 private:
  /// Where `sequence` is, or would go, in pending_.
  std::vector<PlayerInput>::const_iterator slot_of(std::uint32_t sequence) const;

  InputBufferConfig config_;
  std::vector<PlayerInput> pending_;  ///< sorted by sequence, all > last_.sequence
  PlayerInput last_;
};

}  // namespace ricochet::server
