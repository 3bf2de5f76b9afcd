#pragma once
/// Where a match's tick spends its time, per phase, for metrics and benches (as physics'
/// StepProfile is for World::step).

#include <cstdint>
#include <functional>

namespace ricochet::server {

/// A monotonic clock in nanoseconds, read for the profile only, never for game logic. The
/// server passes its steady clock; tests pass a counter; an empty one leaves the phase times 0.
using ProfileClock = std::function<std::int64_t()>;

/// One Match::tick() call: the fixed steps it ran and the wall time of each phase, summed over
/// those steps, in milliseconds.
struct TickProfile {
  int steps = 0;               ///< fixed steps run (0 when none was due)
  bool snapshot = false;       ///< snapshots were built and sent
  double apply_inputs_ms = 0;  ///< one input per player from its jitter buffer
  double rules_ms = 0;         ///< input checks, the match's phase, respawns
  double movement_ms = 0;      ///< ground tests and wished velocities
  double combat_ms = 0;        ///< weapons fired (lag-compensated rays), projectiles, explosions,
                               ///< kill volumes, pickups
  double physics_ms = 0;       ///< World::step
  double history_ms = 0;       ///< the entity states of the step into the history ring, the
                               ///< lag compensation ring and the recording
  double snapshots_ms = 0;     ///< quantisation and one delta-coded snapshot per player
  double send_ms = 0;          ///< events and payloads serialised into the outbox
  double total_ms = 0;

  /// Adds another call's steps and phase times: sums over many ticks (benches, metrics).
  TickProfile& operator+=(const TickProfile& other) {
    steps += other.steps;
    snapshot = snapshot || other.snapshot;
    apply_inputs_ms += other.apply_inputs_ms;
    rules_ms += other.rules_ms;
    movement_ms += other.movement_ms;
    combat_ms += other.combat_ms;
    physics_ms += other.physics_ms;
    history_ms += other.history_ms;
    snapshots_ms += other.snapshots_ms;
    send_ms += other.send_ms;
    total_ms += other.total_ms;
    return *this;
  }
};

}  // namespace ricochet::server
