// A control connection's deadlines on fake time, without sockets: which one comes first in
// each phase, and that dispatching a request holds the idle and frame deadlines but not the
// write deadline; a connection that has not logged in has a login deadline frames do not move.
#include "control_deadlines.h"

#include <gtest/gtest.h>

namespace ricochet::server::control_deadlines_test {
namespace {

constexpr proto::TimeUs kMs = proto::kMicrosPerMilli;

ControlLimits limits() {
  ControlLimits out;
  out.handshake_timeout_ms = 500;
  out.frame_timeout_ms = 300;
  out.idle_timeout_ms = 1000;
  out.write_timeout_ms = 200;
  out.login_timeout_ms = 1500;
  return out;
}

/// An open connection, logged in, whose last frame came at `last_frame_at`.
ControlTimes open_at(proto::TimeUs last_frame_at) {
  ControlTimes times;
  times.phase = ControlPhase::Open;
  times.accepted_at = 0;
  times.last_frame_at = last_frame_at;
  times.logged_in = true;
  return times;
}

void expect_deadline(const std::optional<ControlDeadline>& next, proto::TimeUs at,
                     ControlExpiry expiry) {
  ASSERT_TRUE(next.has_value());
  EXPECT_EQ(next->at, at);
  EXPECT_EQ(next->expiry, expiry);
}

TEST(ControlDeadlines, AHandshakeHasItsTimeoutFromTheAccept) {
  ControlTimes times;
  times.accepted_at = 7 * kMs;
  times.last_frame_at = 0;  // not counted before the connection is open
  expect_deadline(next_deadline(times, limits()), 507 * kMs, ControlExpiry::Handshake);
}

TEST(ControlDeadlines, AnOpenConnectionGoesIdleAfterItsLastFrame) {
  expect_deadline(next_deadline(open_at(40 * kMs), limits()), 1040 * kMs, ControlExpiry::Idle);
}

TEST(ControlDeadlines, APartialFrameMustCompleteFromItsFirstByte) {
  ControlTimes times = open_at(0);
  times.frame_started = 900 * kMs;  // the idle deadline at 1000 ms comes first
  expect_deadline(next_deadline(times, limits()), 1000 * kMs, ControlExpiry::Idle);
  times.frame_started = 100 * kMs;
  expect_deadline(next_deadline(times, limits()), 400 * kMs, ControlExpiry::Frame);
}

TEST(ControlDeadlines, ALoginIsDueFromTheHandshakeWhateverFramesCome) {
  ControlTimes times = open_at(900 * kMs);  // a ping at 900 ms: idle at 1900 ms
  times.logged_in = false;
  times.opened_at = 0;
  expect_deadline(next_deadline(times, limits()), 1500 * kMs, ControlExpiry::Login);
  times.busy = true;  // the login request itself is being dispatched
  EXPECT_FALSE(next_deadline(times, limits()).has_value());
  times.busy = false;
  times.logged_in = true;
  expect_deadline(next_deadline(times, limits()), 1900 * kMs, ControlExpiry::Idle);
}

TEST(ControlDeadlines, AWriteInFlightHasItsOwnDeadline) {
  ControlTimes times = open_at(0);
  times.frame_started = 100 * kMs;
  times.write_started = 150 * kMs;
  expect_deadline(next_deadline(times, limits()), 350 * kMs, ControlExpiry::Write);
}

TEST(ControlDeadlines, DispatchingHoldsTheIdleAndFrameDeadlinesButNotTheWrite) {
  ControlTimes times = open_at(0);
  times.frame_started = 100 * kMs;
  times.busy = true;  // a slow DB call: the client is not to blame
  EXPECT_FALSE(next_deadline(times, limits()).has_value());
  times.write_started = 5000 * kMs;
  expect_deadline(next_deadline(times, limits()), 5200 * kMs, ControlExpiry::Write);
}

TEST(ControlDeadlines, ClosingLeavesTheGraceAndEndedLeavesNothing) {
  ControlTimes times = open_at(0);
  times.write_started = 0;
  times.phase = ControlPhase::Closing;
  times.closing_since = 3000 * kMs;
  expect_deadline(next_deadline(times, limits()), 3000 * kMs + kControlCloseGraceUs,
                  ControlExpiry::CloseGrace);
  times.phase = ControlPhase::Ended;
  EXPECT_FALSE(next_deadline(times, limits()).has_value());
}

TEST(ControlDeadlines, TheLongestTimeoutsDoNotOverflow) {
  ControlLimits longest = limits();
  longest.idle_timeout_ms = 3'600'000;
  const proto::TimeUs late = proto::TimeUs{1} << 60;
  expect_deadline(next_deadline(open_at(late), longest), late + 3'600'000 * kMs,
                  ControlExpiry::Idle);
}

}  // namespace
}  // namespace ricochet::server::control_deadlines_test
