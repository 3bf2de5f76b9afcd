#pragma once
/// Replays a recording (recording.h): applies every recorded membership change and steps with
/// every recorded input, in order, and checks the state hash the recording holds every N ticks.
/// Headless and as fast as the simulation runs; the wall clock is injected.
///
/// The driver knows no Match: it drives a ReplaySimulation, which ricochet-replay implements
/// over Match (Match::apply, step_recorded, state_hash) and tests over a stand-in.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>

#include "ricochet/server/recording.h"

namespace ricochet::server {

/// What a replay drives.
class ReplaySimulation {
 public:
  virtual ~ReplaySimulation() = default;
  /// A membership change recorded before the next step.
  virtual void apply(const RecordedEvent& event) = 0;
  /// The next step, with these inputs (entities without one step with the neutral input).
  virtual void step(std::span<const RecordedInput> inputs) = 0;
  /// The hash the recording holds after a step (Match::state_hash()).
  virtual std::uint64_t state_hash() const = 0;
};

struct ReplayOptions {
  /// Seconds on any monotonic clock; unset: wall_s stays 0.
  std::function<double()> wall_clock_s;
  /// Called after every step with its tick number (the CSV export reads the positions here).
  std::function<void(std::uint32_t tick)> after_step;
  /// Stop at the first hash that differs (else replay to the end and count them all).
  bool stop_at_mismatch = true;
  /// Asked after every step; true stops the replay there (report.stopped). Unset: never.
  std::function<bool()> stop_requested;
};

struct ReplayMismatch {
  std::uint32_t tick = 0;  ///< the first step whose hash differs
  std::uint64_t recorded = 0;
  std::uint64_t replayed = 0;
};

struct ReplayReport {
  std::uint64_t steps = 0;      ///< steps run (ticks the recording skipped included)
  std::uint32_t last_tick = 0;  ///< the last step run
  std::size_t hashes_checked = 0;
  std::size_t hashes_differing = 0;
  std::optional<ReplayMismatch> first_mismatch;  ///< none: every checked hash matched
  double simulated_s = 0;                        ///< steps / tick rate
  double wall_s = 0;                             ///< by options.wall_clock_s
  bool complete = false;                         ///< the recording had its footer
  bool truncated = false;  ///< the recording stopped early (writer at max_bytes)
  bool stopped = false;    ///< options.stop_requested stopped it before the end
};

/// Replays `recording` on `simulation`, which must start as the recorded match started (same
/// config, map and seed, no step run). A tick missing from the recording between two recorded
/// ones is stepped with no inputs and no events.
ReplayReport replay(const Recording& recording, ReplaySimulation& simulation,
                    const ReplayOptions& options = {});

}  // namespace ricochet::server
