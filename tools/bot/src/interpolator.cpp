/// The snapshot buffer and the render time of the other entities (interpolator.h).

#include "ricochet/bot/interpolator.h"

#include <algorithm>
#include <cmath>

#include "ricochet/proto/input_wire.h"

namespace ricochet::bot {

namespace {

/// The render time follows the estimated server tick - delay; it steps there at once when
/// further off than this many delays (a first snapshot, a stall), else closes a tenth of the gap
/// per advance.
constexpr double kSnapDelays = 2;
constexpr double kPull = 0.1;

}  // namespace

Interpolator::Interpolator(std::uint32_t tick_rate_hz, std::uint32_t snapshot_rate_hz)
    : tick_rate_hz_(tick_rate_hz),
      delay_ticks_(std::max(kMinDelayS * tick_rate_hz,
                            kSnapIntervals * double(tick_rate_hz) / double(snapshot_rate_hz))) {}

void Interpolator::add(std::uint32_t tick, std::span<const SeenEntity> entities, double now_s) {
  if (!frames_.empty() && tick <= frames_.back().tick) return;
  if (frames_.empty()) rendered_at_s_ = now_s;
  frames_.push_back({tick, {entities.begin(), entities.end()}});
  newest_at_s_ = now_s;
  if (frames_.size() > kKept) frames_.pop_front();
}

RenderTime Interpolator::advance(double now_s) {
  if (frames_.empty()) return {};
  const double newest = frames_.back().tick;
  const double server_tick = newest + std::max(0.0, now_s - newest_at_s_) * tick_rate_hz_;
  const double target = server_tick - delay_ticks_;
  render_tick_ += std::max(0.0, now_s - rendered_at_s_) * tick_rate_hz_;
  rendered_at_s_ = now_s;
  if (std::fabs(render_tick_ - target) > kSnapDelays * delay_ticks_) {
    render_tick_ = target;
  } else {
    render_tick_ += kPull * (target - render_tick_);
  }
  // Never past the newest snapshot, never before the oldest kept.
  render_tick_ = std::clamp(render_tick_, double(frames_.front().tick), newest);
  interpolate();
  const double whole = std::floor(render_tick_);
  return {static_cast<std::uint32_t>(whole), proto::to_view_fraction(render_tick_ - whole)};
}

void Interpolator::interpolate() {
  // The pair around the render time: the newest frame at or before it, and the next.
  std::size_t before = 0;
  while (before + 1 < frames_.size() && frames_[before + 1].tick <= render_tick_) ++before;
  const Frame& a = frames_[before];
  if (before + 1 == frames_.size() || double(a.tick) == render_tick_) {
    shown_ = a.entities;
    return;
  }
  const Frame& b = frames_[before + 1];
  const float t = static_cast<float>((render_tick_ - a.tick) / double(b.tick - a.tick));
  shown_.clear();
  std::size_t i = 0;
  std::size_t j = 0;
  while (i < a.entities.size() || j < b.entities.size()) {
    if (j == b.entities.size() || (i < a.entities.size() && a.entities[i].id < b.entities[j].id)) {
      shown_.push_back(a.entities[i++]);  // gone by b: as a last saw it
    } else if (i == a.entities.size() || b.entities[j].id < a.entities[i].id) {
      shown_.push_back(b.entities[j++]);  // new in b
    } else {
      const SeenEntity& from = a.entities[i++];
      const SeenEntity& to = b.entities[j++];
      SeenEntity mixed = t < 0.5f ? from : to;
      if (distance_m(from.position_m, to.position_m) <= kJumpM) {
        for (int axis = 0; axis < 3; ++axis) {
          mixed.position_m[axis] =
              from.position_m[axis] + t * (to.position_m[axis] - from.position_m[axis]);
          mixed.velocity_mps[axis] =
              from.velocity_mps[axis] + t * (to.velocity_mps[axis] - from.velocity_mps[axis]);
        }
      } else {
        mixed = to;
      }
      shown_.push_back(mixed);
    }
  }
}

}  // namespace ricochet::bot
