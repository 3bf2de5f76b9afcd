#pragma once
/// The values of a client's Input and ClientPayload (game.proto; PROTOCOL.md `Input` and
/// Client → server): button bits, the move steps and how they become a stick vector, the angle
/// ranges, the 1/256-tick view fraction, and how many inputs a payload may carry. The server
/// checks inputs against these and a client builds them with them.

#include <cstddef>
#include <cstdint>
#include <numbers>

#include "ricochet/proto/packet.h"

namespace ricochet::proto {

/// Bits of Input.buttons; any other bit is refused.
enum Button : std::uint32_t {
  kButtonJump = 1u << 0,
  kButtonFire = 1u << 1,
  kButtonAltFire = 1u << 2,
};
inline constexpr std::uint32_t kKnownButtons = kButtonJump | kButtonFire | kButtonAltFire;

/// Input.move_right and move_forward lie in -kMoveSteps..kMoveSteps: k/127 of full input.
inline constexpr std::int32_t kMoveSteps = 127;

/// The move of an input in the player's yaw frame, each -1..1, of length <= 1.
struct Stick {
  float right = 0;
  float forward = 0;
  friend bool operator==(const Stick&, const Stick&) = default;
};

/// (move_right, move_forward) / kMoveSteps in single precision, shortened to length 1 when
/// longer (a full diagonal). The server moves a player by exactly this; a client that predicts
/// must use it too. The steps must be within ±kMoveSteps (the server refuses others).
Stick stick_of(std::int32_t move_right, std::int32_t move_forward);

/// The move steps nearest to `fraction` of full input (clamped to -1..1).
std::int32_t move_steps(float fraction);

/// Input.yaw lies within ±kMaxYawRad, rad.
inline constexpr float kMaxYawRad = 2 * std::numbers::pi_v<float>;
/// Input.pitch lies within ±kMaxPitchRad, rad (the server allows float rounding past it).
inline constexpr float kMaxPitchRad = std::numbers::pi_v<float> / 2;

/// Input.view_fraction counts 1/kViewFractionSteps of a tick past Input.view_tick: 0..255.
inline constexpr std::uint32_t kViewFractionSteps = 256;

/// The part of a tick `view_fraction` stands for, ticks: 0..255/256.
constexpr double view_fraction_ticks(std::uint8_t view_fraction) {
  return view_fraction / static_cast<double>(kViewFractionSteps);
}

/// The view_fraction of `ticks_past` (a part of a tick, 0..1), rounded down, at most 255.
std::uint8_t to_view_fraction(double ticks_past);

/// A ClientPayload carries at most this many inputs (more: the whole payload is dropped).
inline constexpr std::size_t kMaxInputsPerPayload = 8;
/// Largest serialised ClientPayload accepted, bytes: a game datagram.
inline constexpr std::size_t kMaxClientPayloadBytes = kMaxDatagramBytes;

}  // namespace ricochet::proto
