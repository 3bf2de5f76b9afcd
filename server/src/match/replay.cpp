/// The replay driver (replay.h).

#include "ricochet/server/replay.h"

namespace ricochet::server {

ReplayReport replay(const Recording& recording, ReplaySimulation& simulation,
                    const ReplayOptions& options) {
  ReplayReport report;
  report.complete = recording.complete;
  report.truncated = recording.truncated;
  const double started_s = options.wall_clock_s ? options.wall_clock_s() : 0;
  std::size_t next_hash = 0;
  const auto check = [&] {
    while (next_hash < recording.hashes.size() &&
           recording.hashes[next_hash].tick < report.last_tick) {
      ++next_hash;  // read_recording() never gives these; a hand-made Recording might
    }
    if (next_hash == recording.hashes.size() ||
        recording.hashes[next_hash].tick != report.last_tick) {
      return true;
    }
    const std::uint64_t recorded = recording.hashes[next_hash++].hash;
    const std::uint64_t replayed = simulation.state_hash();
    ++report.hashes_checked;
    if (recorded == replayed) return true;
    ++report.hashes_differing;
    if (!report.first_mismatch)
      report.first_mismatch = ReplayMismatch{report.last_tick, recorded, replayed};
    return !options.stop_at_mismatch;
  };
  const auto step = [&](std::span<const RecordedInput> inputs) {
    simulation.step(inputs);
    ++report.steps;
    ++report.last_tick;
    if (options.after_step) options.after_step(report.last_tick);
    if (!check()) return false;
    report.stopped = options.stop_requested && options.stop_requested();
    return !report.stopped;
  };
  bool going = true;
  for (const RecordedTick& tick : recording.ticks) {
    while (going && report.last_tick + 1 < tick.tick) going = step({});
    if (!going) break;
    for (const RecordedEvent& event : tick.events) simulation.apply(event);
    going = step(tick.inputs);
  }
  const std::uint32_t rate = recording.header.tick_rate_hz == 0 ? 1 : recording.header.tick_rate_hz;
  report.simulated_s = static_cast<double>(report.steps) / rate;
  if (options.wall_clock_s) report.wall_s = options.wall_clock_s() - started_s;
  return report;
}

}  // namespace ricochet::server
