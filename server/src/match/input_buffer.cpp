/// Input validation and the per-client jitter buffer (input_buffer.h).

#include "ricochet/server/input_buffer.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "ricochet/proto/weapon_wire.h"

namespace ricochet::server {

namespace {

/// Inputs further ahead than this are not a network delay but a bogus sequence.
constexpr std::uint32_t kMaxSequenceLead = 1024;

}  // namespace

const char* name(InputDrop reason) {
  switch (reason) {
    case InputDrop::MalformedPayload:
      return "malformed_payload";
    case InputDrop::TooManyInputs:
      return "too_many_inputs";
    case InputDrop::NonFinite:
      return "non_finite";
    case InputDrop::OutOfRange:
      return "out_of_range";
    case InputDrop::ZeroSequence:
      return "zero_sequence";
    case InputDrop::Stale:
      return "stale";
    case InputDrop::TooFarAhead:
      return "too_far_ahead";
    case InputDrop::Skipped:
      return "skipped";
    case InputDrop::UnknownPlayer:
      return "unknown_player";
  }
  return "unknown";
}

bool validate_input(const wire::Input& in, PlayerInput& out, InputDrop& reason) {
  if (!std::isfinite(in.yaw()) || !std::isfinite(in.pitch())) {
    reason = InputDrop::NonFinite;
    return false;
  }
  if (in.sequence() == 0) {
    reason = InputDrop::ZeroSequence;
    return false;
  }
  const auto move_ok = [](std::int32_t steps) {
    return steps >= -proto::kMoveSteps && steps <= proto::kMoveSteps;
  };
  const bool in_range =
      move_ok(in.move_right()) && move_ok(in.move_forward()) &&
      std::abs(in.yaw()) <= proto::kMaxYawRad && std::abs(in.pitch()) <= kAcceptedMaxPitchRad &&
      (in.buttons() & ~proto::kKnownButtons) == 0 && in.weapon_slot() <= proto::kMaxWeaponSlot &&
      in.view_fraction() < proto::kViewFractionSteps;
  if (!in_range) {
    reason = InputDrop::OutOfRange;
    return false;
  }
  out.sequence = in.sequence();
  const proto::Stick stick = proto::stick_of(in.move_right(), in.move_forward());
  out.move_right = stick.right;
  out.move_forward = stick.forward;
  out.yaw_rad = in.yaw();
  out.pitch_rad = in.pitch();
  out.buttons = in.buttons();
  out.weapon_slot = in.weapon_slot();
  out.view_tick = in.view_tick();
  out.view_fraction = static_cast<std::uint8_t>(in.view_fraction());
  return true;
}

std::string InputBufferConfig::validate() const {
  if (max_depth < 1 || max_depth > 32) {
    return "input max_depth must be 1..32, got " + std::to_string(max_depth);
  }
  return {};
}

InputBuffer::InputBuffer(const InputBufferConfig& config) : config_(config) {
  pending_.reserve(config_.max_depth + 1);
}

std::vector<PlayerInput>::const_iterator InputBuffer::slot_of(std::uint32_t sequence) const {
  return std::lower_bound(
      pending_.begin(), pending_.end(), sequence,
      [](const PlayerInput& kept, std::uint32_t wanted) { return kept.sequence < wanted; });
}

bool InputBuffer::is_new(std::uint32_t sequence) const {
  if (sequence <= last_.sequence) return false;
  const auto at = slot_of(sequence);
  return at == pending_.end() || at->sequence != sequence;
}

void InputBuffer::offer(const PlayerInput& input, InputDropCounters& drops) {
  const auto count = [&drops](InputDrop reason) { ++drops[static_cast<std::size_t>(reason)]; };
  if (!is_new(input.sequence)) return count(InputDrop::Stale);
  if (input.sequence - last_.sequence > kMaxSequenceLead) return count(InputDrop::TooFarAhead);
  pending_.insert(slot_of(input.sequence), input);
  if (pending_.size() > config_.max_depth) {
    pending_.erase(pending_.begin());
    count(InputDrop::Skipped);
  }
}

const PlayerInput& InputBuffer::next(bool& repeated) {
  repeated = pending_.empty();
  if (!repeated) {
    last_ = pending_.front();
    pending_.erase(pending_.begin());
  }
  return last_;
}

void InputBuffer::reset() {
  pending_.clear();
  last_ = PlayerInput{};
}

}  // namespace ricochet::server
