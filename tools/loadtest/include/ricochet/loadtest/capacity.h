#pragma once
/// The capacity rule behind the headline figure (capacity_bots in report.json): a sweep's
/// capacity is its largest step whose measured window meets every criterion below.

#include <cstdint>
#include <vector>

#include "ricochet/loadtest/run_record.h"

namespace ricochet::loadtest {

/// What a step's measured window must show to count towards capacity.
struct CapacityCriteria {
  /// The worst match's tick p99 over its last 600 ticks (/metrics, nearest rank), at most, ms:
  /// a quarter of the 16.7 ms period at 60 Hz, so a tick's tail leaves the core room for the
  /// network and the other matches due on the same wake.
  double max_tick_p99_ms = 4.0;
  /// Ticks that hit the catch-up cap during the window, at most.
  double max_overruns = 0;
  /// The bots' lost snapshots over received + lost during the window, at most, 0..1.
  double max_snapshot_loss = 0.01;
  /// The server's CPU over the window, below, % of one core: a saturated core starts ticks late.
  double server_cpu_percent_below = 90;
};

inline constexpr CapacityCriteria kCapacityCriteria{};

/// The generator's CPU, % of its core, from which its own core rather than the server may be
/// what limits the step (report.json "generator_saturated").
inline constexpr double kGeneratorSaturatedCpuPercent = 90;

/// A criterion a step misses.
enum class CapacityShortfall : std::uint8_t {
  NotMeasured,   ///< the window is empty
  BotsMissing,   ///< not every bot of the step is playing at the window's end
  TickP99,       ///< max_tick_p99_ms exceeded
  Overruns,      ///< max_overruns exceeded
  SnapshotLoss,  ///< max_snapshot_loss exceeded
  ServerCpu,     ///< server_cpu_percent_below not kept
};

/// "not_measured", "bots_missing", "tick_p99", "overruns", "snapshot_loss", "server_cpu".
const char* name(CapacityShortfall shortfall);

/// Every criterion the step misses, in the order of CapacityShortfall; empty: it meets them all.
std::vector<CapacityShortfall> capacity_shortfalls(
    const StepSummary& step, const CapacityCriteria& criteria = kCapacityCriteria);

/// A sweep's capacity: the largest step that meets the criteria; 0 when none does.
int capacity_bots(const std::vector<StepSummary>& steps);

}  // namespace ricochet::loadtest
