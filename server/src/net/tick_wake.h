#pragma once
/// When a match's host wakes its timer for a tick: a little after the tick is due, on a grid
/// shared by every match, so that the matches of one server whose ticks fall due close together
/// are woken by one timer expiry instead of each by its own.
///
/// Every wake of an idle thread is a sleep, a timerfd_settime and a context switch, which costs
/// more than an empty match's whole tick. With one wake per match per tick, a server hosting many
/// empty matches spent much of its core on nothing but waking (the figures before and after:
/// tools/bench/results/server-io.md). On a grid of 1 ms it wakes at most 1 000 times a second
/// whatever the number of matches.
///
/// The price is that a tick runs up to one grain late by the wall clock. The simulation does not
/// see it (a step's time is its number times the period: TickClock), and a snapshot leaves at
/// most one grain later than it would have: a 60 Hz tick is 16.7 ms, the grain 1 ms.

#include <algorithm>

#include "ricochet/proto/clock.h"

namespace ricochet::server {

/// The grid's spacing: 1 ms, or an eighth of the tick period at rates over 125 Hz. µs.
constexpr proto::TimeUs tick_wake_grain_us(int tick_rate_hz) {
  return std::min<proto::TimeUs>(1000, proto::kMicrosPerSecond / (8 * tick_rate_hz));
}

/// The first grid point at or after `due` (steady µs; due ≥ 0): when to wake for a tick due then.
constexpr proto::TimeUs tick_wake_at(proto::TimeUs due, int tick_rate_hz) {
  const proto::TimeUs grain = tick_wake_grain_us(tick_rate_hz);
  return (due + grain - 1) / grain * grain;
}

}  // namespace ricochet::server
