#pragma once
/// Interpolation of the other entities between snapshots, sans-IO. A buffer of the newest
/// decoded snapshots; the render time trails the server's tick (the newest snapshot's, plus the
/// bot's clock since it arrived) by the interpolation delay, closing a tenth of any gap per
/// advance, so that what the bot shows moves smoothly; it is always between two snapshots it has
/// (never extrapolated: a stall stops it at the newest).
///
/// Delay: max(100 ms, 2 snapshot intervals), in ticks, so that one lost snapshot still leaves a
/// pair to interpolate between. The tick and fraction shown are what the bot's inputs claim as
/// their view (Input.view_tick, view_fraction): lag compensation rewinds to them.

#include <cstddef>
#include <cstdint>
#include <deque>
#include <span>
#include <vector>

#include "ricochet/bot/world_view.h"

namespace ricochet::bot {

/// What the bot renders at one moment.
struct RenderTime {
  std::uint32_t tick = 0;     ///< 0: nothing to show yet
  std::uint8_t fraction = 0;  ///< 1/256 of a tick past `tick` (proto::to_view_fraction)
};

class Interpolator {
 public:
  static constexpr std::size_t kKept = 32;     ///< snapshots buffered
  static constexpr double kMinDelayS = 0.1;    ///< the delay's floor, s
  static constexpr double kSnapIntervals = 2;  ///< the delay in snapshot intervals
  /// Entities that moved more than this between two snapshots jumped (a respawn): not lerped.
  static constexpr float kJumpM = 3;

  /// tick_rate_hz, snapshot_rate_hz: the join reply's (validated).
  Interpolator(std::uint32_t tick_rate_hz, std::uint32_t snapshot_rate_hz);

  /// A decoded snapshot (entities sorted by id) that arrived at `now_s` (the bot's clock, s);
  /// one not newer than every one before is ignored.
  void add(std::uint32_t tick, std::span<const SeenEntity> entities, double now_s);
  /// Moves the render time on to `now_s` (the bot's clock, s, not decreasing) and returns it.
  RenderTime advance(double now_s);
  /// The entities at the current render time, sorted by id (an entity in only one of the two
  /// snapshots around it is shown as that one has it).
  const std::vector<SeenEntity>& entities() const { return shown_; }

  double delay_ticks() const { return delay_ticks_; }

 private:
  struct Frame {
    std::uint32_t tick = 0;
    std::vector<SeenEntity> entities;
  };
  void interpolate();

  double tick_rate_hz_;
  double delay_ticks_;
  std::deque<Frame> frames_;
  double render_tick_ = 0;    ///< fractional server tick shown
  double newest_at_s_ = 0;    ///< when the newest snapshot arrived
  double rendered_at_s_ = 0;  ///< the last advance
  std::vector<SeenEntity> shown_;
};

}  // namespace ricochet::bot
