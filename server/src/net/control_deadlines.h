#pragma once
/// The deadlines of one control connection, without I/O: the session keeps when things
/// happened (µs on the control server's clock) in a ControlTimes, and next_deadline() says
/// which deadline comes first and when. The session's watchdog timer waits until then, reads
/// the clock and expires the connection if the deadline still holds.
///
///   Handshake  accepted_at + handshake_timeout_ms
///   Open       the earliest of
///                idle   last_frame_at + idle_timeout_ms       } wait while a request is
///                frame  frame_started + frame_timeout_ms      } dispatched (busy)
///                login  opened_at + login_timeout_ms          } until logged in
///                write  write_started + write_timeout_ms
///   Closing    closing_since + the close grace (the final Error's time to be written)
///   Ended      none

#include <optional>

#include "control_config.h"
#include "ricochet/proto/clock.h"

namespace ricochet::server {

/// Where a control session is in its life: TLS handshake, frames flowing, flushing its final
/// message, over.
enum class ControlPhase { Handshake, Open, Closing, Ended };

/// Which deadline ran out.
enum class ControlExpiry { Handshake, Frame, Idle, Login, Write, CloseGrace };

/// After close(), the final Error gets this long to be written before the socket is closed.
inline constexpr proto::TimeUs kControlCloseGraceUs = 2 * proto::kMicrosPerSecond;

/// When the events the deadlines count from happened, in µs on the control server's clock.
struct ControlTimes {
  ControlPhase phase = ControlPhase::Handshake;
  proto::TimeUs accepted_at = 0;
  proto::TimeUs last_frame_at = 0;  ///< the last whole frame was answered, or the handshake ended
  proto::TimeUs closing_since = 0;
  proto::TimeUs opened_at = 0;  ///< the TLS handshake ended
  bool logged_in = false;       ///< a login or resume succeeded: no login deadline any more
  std::optional<proto::TimeUs> frame_started;  ///< the first byte of a frame not yet whole
  std::optional<proto::TimeUs> write_started;  ///< a write is in flight since
  bool busy = false;  ///< a request is being dispatched: the idle and frame deadlines wait
};

struct ControlDeadline {
  proto::TimeUs at = 0;  ///< µs on the same clock as the ControlTimes
  ControlExpiry expiry = ControlExpiry::Idle;
};

/// The first deadline of `times` under `limits`; none when the session has ended. Ties go to
/// the first of idle, frame, login, write.
std::optional<ControlDeadline> next_deadline(const ControlTimes& times,
                                             const ControlLimits& limits);

}  // namespace ricochet::server
