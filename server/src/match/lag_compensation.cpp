/// The per-tick ring of player spheres, the view time a shot is tested at, and the rewound
/// hitscan (lag_compensation.h).

#include "ricochet/server/lag_compensation.h"

#include <algorithm>
#include <cmath>

#include "range_check.h"
#include "ricochet/proto/input_wire.h"

namespace ricochet::server {

namespace {

/// The sample of `entity` in `samples`, looked up first at `hint` (players keep their index
/// from tick to tick), or nullptr.
const LagSample* find_sample(const std::vector<LagSample>& samples, std::uint32_t entity,
                             std::size_t hint) {
  if (hint < samples.size() && samples[hint].entity_id == entity) return &samples[hint];
  for (const LagSample& sample : samples) {
    if (sample.entity_id == entity) return &sample;
  }
  return nullptr;
}

/// Whether `then` is on the same track as `now`: alive then, and neither respawned nor
/// teleported since.
bool same_track(const LagSample* then, const LagSample& now) {
  return then != nullptr && then->hittable && then->life == now.life;
}

}  // namespace

std::string LagCompensationConfig::validate() const {
  if (!within(history_s, 0.1f, 2))
    return range_error("lag_compensation", "history_s", "0.1..2", history_s);
  if (!within(max_rewind_ms, 0, history_s * 1000)) {
    std::string range = "0..";
    range += std::to_string(std::lround(history_s * 1000));
    range += " (history_s in ms)";
    return range_error("lag_compensation", "max_rewind_ms", range, max_rewind_ms);
  }
  if (!within(claim_tolerance_ms, 0, 1000)) {
    return range_error("lag_compensation", "claim_tolerance_ms", "0..1000", claim_tolerance_ms);
  }
  if (!within(interpolation_delay_ms, 0, 250)) {
    return range_error("lag_compensation", "interpolation_delay_ms", "0..250",
                       interpolation_delay_ms);
  }
  return {};
}

LagCompensation::LagCompensation(const LagCompensationConfig& config, int tick_rate_hz)
    : config_(config),
      tick_rate_hz_(std::max(tick_rate_hz, 1)),
      ring_(static_cast<std::size_t>(std::ceil(config.history_s * tick_rate_hz_)) + 1) {}

void LagCompensation::record(std::uint32_t tick, std::span<const LagSample> players) {
  // A tick not after the newest starts a new history (the ring is read only from oldest_tick_).
  if (!any_ || tick <= newest_tick_) oldest_tick_ = tick;
  any_ = true;
  newest_tick_ = tick;
  const auto size = static_cast<std::uint32_t>(ring_.size());
  if (newest_tick_ - oldest_tick_ >= size) oldest_tick_ = newest_tick_ - size + 1;
  Slot& slot = ring_[tick % size];
  slot.tick = tick;
  slot.used = true;
  slot.samples.assign(players.begin(), players.end());
}

const LagCompensation::Slot* LagCompensation::slot_of(std::uint32_t tick) const {
  if (!any_ || tick < oldest_tick_ || tick > newest_tick_) return nullptr;
  const Slot& slot = ring_[tick % ring_.size()];
  return slot.used && slot.tick == tick ? &slot : nullptr;
}

ViewTime LagCompensation::resolve(std::uint32_t now_tick, std::uint32_t claimed_tick,
                                  std::uint8_t claimed_fraction, double one_way_latency_ms) const {
  ViewTime view;
  view.tick = now_tick;
  if (!config_.enabled) return view;

  const double max_rewind_ms = config_.max_rewind_ms;
  const double latency_ms =
      std::isfinite(one_way_latency_ms) && one_way_latency_ms > 0 ? one_way_latency_ms : 0;
  const double estimate_ms =
      std::clamp(latency_ms + config_.interpolation_delay_ms, 0.0, max_rewind_ms);
  double rewind_ms = estimate_ms;
  if (claimed_tick != 0) {
    const double claimed_ticks = claimed_tick + proto::view_fraction_ticks(claimed_fraction);
    const double claimed_ms = (static_cast<double>(now_tick) - claimed_ticks) * tick_ms();
    const double low_ms = std::max(0.0, estimate_ms - config_.claim_tolerance_ms);
    const double high_ms = std::min(max_rewind_ms, estimate_ms + config_.claim_tolerance_ms);
    if (claimed_ms >= low_ms && claimed_ms <= high_ms) {
      // Trusted: the client's own tick and fraction, exactly.
      view.tick = claimed_tick;
      view.fraction = static_cast<float>(proto::view_fraction_ticks(claimed_fraction));
      view.rewind_ms = claimed_ms;
      return view;
    }
    view.clamped = true;
    ++clamped_claims_;
    rewind_ms = std::clamp(claimed_ms, low_ms, high_ms);
  }
  const double view_ticks = std::max(0.0, static_cast<double>(now_tick) - rewind_ms / tick_ms());
  const double whole = std::floor(view_ticks);
  view.tick = static_cast<std::uint32_t>(whole);
  view.fraction = static_cast<float>(view_ticks - whole);
  view.rewind_ms = (static_cast<double>(now_tick) - view_ticks) * tick_ms();
  return view;
}

void LagCompensation::rewound_targets(const ViewTime& view, std::uint32_t shooter_entity,
                                      std::vector<physics::SphereProxy>& out) const {
  out.clear();
  const Slot* now = slot_of(newest_tick_);
  if (now == nullptr) return;

  // Never extrapolate: a view at or after the newest tick is the newest tick; one older than
  // the ring is its oldest tick.
  std::uint32_t tick = view.tick;
  float fraction = std::isfinite(view.fraction) ? std::clamp(view.fraction, 0.0f, 1.0f) : 0.0f;
  if (tick >= newest_tick_) {
    tick = newest_tick_;
    fraction = 0;
  } else if (tick < oldest_tick_) {
    tick = oldest_tick_;
    fraction = 0;
  }
  const Slot* older = config_.enabled ? slot_of(tick) : nullptr;
  const Slot* newer = fraction > 0 ? slot_of(tick + 1) : older;

  for (std::size_t i = 0; i < now->samples.size(); ++i) {
    const LagSample& current = now->samples[i];
    if (current.entity_id == shooter_entity || !current.hittable) continue;
    physics::Vec3 center = current.position_m;
    if (older != nullptr && newer != nullptr) {
      const LagSample* a = find_sample(older->samples, current.entity_id, i);
      const LagSample* b = newer == older ? a : find_sample(newer->samples, current.entity_id, i);
      if (same_track(a, current) && same_track(b, current)) {
        center = a->position_m + (b->position_m - a->position_m) * physics::Real(fraction);
      }
    }
    physics::SphereProxy proxy;
    proxy.center = center;
    proxy.radius = current.radius_m;
    proxy.body = current.body;
    proxy.user_data = current.entity_id;
    out.push_back(proxy);
  }
}

bool LagCompensation::cast(const physics::World& world, const physics::Vec3& origin,
                           const physics::Vec3& direction, physics::Real max_distance,
                           const ViewTime& view, std::uint32_t shooter_entity,
                           physics::RayHit& hit) const {
  rewound_targets(view, shooter_entity, scratch_);
  physics::QueryFilter filter;
  filter.bodies = false;  // the live players are stood in for by the rewound spheres
  filter.statics = true;
  return world.ray_cast_spheres(origin, direction, max_distance, filter, scratch_, hit);
}

}  // namespace ricochet::server
