#include "control_deadlines.h"

namespace ricochet::server {
namespace {

proto::TimeUs after_ms(proto::TimeUs at, std::uint32_t ms) {
  return at + static_cast<proto::TimeUs>(ms) * proto::kMicrosPerMilli;
}

}  // namespace

std::optional<ControlDeadline> next_deadline(const ControlTimes& times,
                                             const ControlLimits& limits) {
  switch (times.phase) {
    case ControlPhase::Handshake:
      return ControlDeadline{after_ms(times.accepted_at, limits.handshake_timeout_ms),
                             ControlExpiry::Handshake};
    case ControlPhase::Closing:
      return ControlDeadline{times.closing_since + kControlCloseGraceUs, ControlExpiry::CloseGrace};
    case ControlPhase::Ended:
      return std::nullopt;
    case ControlPhase::Open:
      break;
  }
  std::optional<ControlDeadline> next;
  const auto consider = [&next](proto::TimeUs at, ControlExpiry expiry) {
    if (!next || at < next->at) next = ControlDeadline{at, expiry};
  };
  if (!times.busy) {
    consider(after_ms(times.last_frame_at, limits.idle_timeout_ms), ControlExpiry::Idle);
    if (times.frame_started) {
      consider(after_ms(*times.frame_started, limits.frame_timeout_ms), ControlExpiry::Frame);
    }
    if (!times.logged_in) {
      consider(after_ms(times.opened_at, limits.login_timeout_ms), ControlExpiry::Login);
    }
  }
  if (times.write_started) {
    consider(after_ms(*times.write_started, limits.write_timeout_ms), ControlExpiry::Write);
  }
  return next;
}

}  // namespace ricochet::server
