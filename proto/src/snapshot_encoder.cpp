/// SnapshotEncoder: chooses what to send against the acknowledged baseline, within the budget,
/// and writes the stream (PROTOCOL.snapshot.md §stream).

#include <algorithm>
#include <cassert>
#include <cmath>

#include "ricochet/proto/bit_stream.h"
#include "ricochet/proto/snapshot_codec.h"
#include "snapshot_layout.h"
#include "snapshot_orders.h"

namespace ricochet::proto {

namespace layout = snapshot_layout;

namespace {

/// Removals go before everything: they are cheap and a gone entity must not linger.
constexpr float kRemovalPriority = 1e9f;
/// A new entity counts as this much change, m.
constexpr float kNewEntityChange_m = 1.0f;
/// How much a changed flag byte or orientation counts, m.
constexpr float kFlagsChange_m = 1.0f;
constexpr float kOrientationChange_m = 0.05f;
/// Velocity change counts as the distance it covers in this long, s.
constexpr float kVelocityHorizon_s = 0.1f;
/// A changed entity counts at least this much, m, however small its change.
constexpr float kMinimumChange_m = 0.01f;

std::size_t varint_bytes(std::uint64_t value) {
  std::size_t bytes = 1;
  while (value >= 0x80) {
    value >>= 7;
    ++bytes;
  }
  return bytes;
}

/// Bytes of a wire::Snapshot around an entity stream of at most budget_bytes.
std::size_t header_bytes(std::uint32_t tick, std::uint32_t baseline_age, std::size_t budget_bytes) {
  std::size_t bytes = 1 + varint_bytes(tick) + 1 + varint_bytes(budget_bytes);
  if (baseline_age != 0) bytes += 1 + varint_bytes(baseline_age);
  return bytes;
}

}  // namespace

struct SnapshotEncoder::Candidate {
  enum class Kind : std::uint8_t { Removed, Added, Changed };
  Kind kind = Kind::Changed;
  std::uint32_t baseline_index = 0;  ///< Removed, Changed
  std::uint32_t world_index = 0;     ///< Added, Changed
  float priority = 0;
  int bits = 0;  ///< estimate, for the budget
  bool selected = false;
};

std::string SnapshotEncoderOptions::validate() const {
  if (ring_size < 2 || ring_size > 1024) {
    return "ring_size must be 2..1024, got " + std::to_string(ring_size);
  }
  if (!(distance_scale_m > 0) || !std::isfinite(distance_scale_m)) {
    return "distance_scale_m must be finite and > 0, got " + std::to_string(distance_scale_m);
  }
  return {};
}

SnapshotEncoder::SnapshotEncoder(QuantizationSpec spec, SnapshotEncoderOptions options)
    : spec_(spec), options_(options), ring_(options.ring_size) {
  assert(spec_.validate().empty() && options_.validate().empty());
}

void SnapshotEncoder::acknowledge(std::uint32_t tick) {
  const Sent& sent = slot(tick);
  if (!sent.valid || sent.tick != tick || (has_ack_ && tick <= acked_tick_)) {
    ++ignored_acks_;
    return;
  }
  has_ack_ = true;
  acked_tick_ = tick;
}

void SnapshotEncoder::encode(std::uint32_t tick, std::span<const QuantizedEntity> world,
                             std::array<float, 3> viewer_m, std::size_t budget_bytes,
                             wire::Snapshot& out) {
  assert(!has_sent_ || tick > last_tick_);
  assert(std::is_sorted(world.begin(), world.end(),
                        [](const auto& a, const auto& b) { return a.id < b.id; }));
  const layout::FieldWidths widths(spec_);

  // The baseline: the newest acknowledged snapshot, while the ring still holds it.
  const Sent& acked = slot(acked_tick_);
  const bool has_baseline = has_ack_ && acked.valid && acked.tick == acked_tick_;
  const std::span<const QuantizedEntity> baseline =
      has_baseline ? std::span<const QuantizedEntity>(acked.view)
                   : std::span<const QuantizedEntity>();
  const std::uint32_t baseline_age = has_baseline ? tick - acked_tick_ : 0;

  // What differs from the baseline, each with its accumulated priority.
  std::vector<Candidate> candidates;
  auto carried_priority = [this, p = std::size_t{0}](std::uint32_t id) mutable {
    while (p < priority_.size() && priority_[p].first < id) ++p;
    return p < priority_.size() && priority_[p].first == id ? priority_[p].second : 0.0f;
  };
  auto distance_weight = [&](const QuantizedEntity& entity) {
    double squared = 0;
    for (int a = 0; a < 3; ++a) {
      const double d = spec_.bounds.min_m[a] +
                       static_cast<double>(entity.position[a]) * spec_.position_step_m -
                       viewer_m[a];
      squared += d * d;
    }
    return static_cast<float>(1.0 / (1.0 + std::sqrt(squared) / options_.distance_scale_m));
  };
  auto add_world_candidate = [&](Candidate candidate, float change_m) {
    const QuantizedEntity& entity = world[candidate.world_index];
    candidate.priority = carried_priority(entity.id) + change_m * distance_weight(entity);
    candidates.push_back(candidate);
  };
  std::size_t i = 0, j = 0;
  while (i < world.size() || j < baseline.size()) {
    if (i == world.size() || (j < baseline.size() && baseline[j].id < world[i].id)) {
      Candidate removed{
          Candidate::Kind::Removed, static_cast<std::uint32_t>(j), 0, kRemovalPriority, 0, false};
      candidates.push_back(removed);
      ++j;
    } else if (j == baseline.size() || world[i].id < baseline[j].id) {
      add_world_candidate({Candidate::Kind::Added, 0, static_cast<std::uint32_t>(i), 0,
                           layout::absolute_bits(world[i], widths), false},
                          kNewEntityChange_m);
      ++i;
    } else {
      const QuantizedEntity& now = world[i];
      const QuantizedEntity& then = baseline[j];
      if (now != then) {
        double moved_m = 0, velocity_mps = 0;
        for (int a = 0; a < 3; ++a) {
          moved_m += std::fabs(static_cast<double>(now.position[a]) - then.position[a]) *
                     spec_.position_step_m;
          velocity_mps += std::fabs(static_cast<double>(now.velocity[a]) - then.velocity[a]) *
                          spec_.velocity_step_mps;
        }
        const bool turned = then.orientation_largest != now.orientation_largest ||
                            then.orientation != now.orientation;
        const double change_m = kMinimumChange_m + moved_m + velocity_mps * kVelocityHorizon_s +
                                (turned ? kOrientationChange_m : 0) +
                                (then.flags != now.flags ? kFlagsChange_m : 0);
        add_world_candidate({Candidate::Kind::Changed, static_cast<std::uint32_t>(j),
                             static_cast<std::uint32_t>(i), 0, 0, false},
                            static_cast<float>(change_m));
      }
      ++i;
      ++j;
    }
  }

  // Orders for the whole set, to estimate each candidate's cost.
  const layout::Prediction prediction = layout::make_prediction(baseline_age, spec_);
  layout::DeltaOrders orders;
  {
    std::array<std::vector<std::uint64_t>, 3> position, velocity;
    std::vector<std::uint64_t> orientation;
    for (const Candidate& c : candidates) {
      if (c.kind != Candidate::Kind::Changed) continue;
      const QuantizedEntity& now = world[c.world_index];
      const QuantizedEntity& then = baseline[c.baseline_index];
      const std::uint8_t fields = layout::changed_fields(then, now, prediction);
      const std::array<std::int64_t, 3> residual = layout::position_residual(then, now, prediction);
      for (int a = 0; a < 3; ++a) {
        if (fields & layout::kPositionChanged) position[a].push_back(zigzag(residual[a]));
        if (fields & layout::kVelocityChanged) {
          velocity[a].push_back(
              zigzag(static_cast<std::int64_t>(now.velocity[a]) - then.velocity[a]));
        }
        if ((fields & layout::kOrientationChanged) &&
            now.orientation_largest == then.orientation_largest) {
          orientation.push_back(
              zigzag(static_cast<std::int64_t>(now.orientation[a]) - then.orientation[a]));
        }
      }
    }
    for (int a = 0; a < 3; ++a) {
      orders.position[a] = layout::best_order(position[a]);
      orders.velocity[a] = layout::best_order(velocity[a]);
    }
    orders.orientation = layout::best_order(orientation);
  }
  std::size_t changed_total = 0;
  for (const Candidate& c : candidates) changed_total += c.kind == Candidate::Kind::Changed;
  const int gap_estimate =
      exp_golomb_bits(changed_total == 0 ? 0 : baseline.size() / changed_total, 0);
  for (Candidate& c : candidates) {
    if (c.kind == Candidate::Kind::Changed) {
      c.bits = layout::delta_bits(baseline[c.baseline_index], world[c.world_index], orders, widths,
                                  prediction) +
               gap_estimate;
    } else if (c.kind == Candidate::Kind::Removed) {
      c.bits = 2 * bits_for_count(baseline.size() + 1) + 1;
    } else {
      c.bits += 2 * bits_for_count(world.size() + 1) + 1;
    }
  }

  // Select within the budget: everything when it fits, else greedily by priority.
  const std::size_t header = header_bytes(tick, baseline_age, budget_bytes);
  // Counts, orders and padding.
  const std::size_t fixed_bits = 3 + (2 + layout::kDeltaOrderCount) * layout::kOrderBits + 8;
  std::size_t budget_bits = budget_bytes > header ? (budget_bytes - header) * 8 : 0;
  budget_bits = budget_bits > fixed_bits ? budget_bits - fixed_bits : 0;
  std::vector<std::uint32_t> by_priority(candidates.size());
  for (std::uint32_t k = 0; k < by_priority.size(); ++k) by_priority[k] = k;
  std::stable_sort(by_priority.begin(), by_priority.end(), [&](std::uint32_t a, std::uint32_t b) {
    return candidates[a].priority > candidates[b].priority;
  });
  std::size_t selected_count = 0;
  {
    std::size_t used = 0;
    for (const std::uint32_t k : by_priority) {
      if (used + candidates[k].bits > budget_bits) break;
      used += candidates[k].bits;
      candidates[k].selected = true;
      ++selected_count;
    }
  }

  // Write; while the real stream overshoots the estimate, leave out the lowest priorities.
  BitWriter stream;
  for (;;) {
    stream.clear();
    next_view_.clear();
    // Removals, as gaps between baseline indices.
    std::vector<std::uint64_t> removed_gaps, added_gaps, changed_gaps;
    std::vector<std::uint32_t> removed_at(baseline.size() + 1, 0);  // removals before index
    {
      std::int64_t previous = -1;
      for (const Candidate& c : candidates) {
        if (!c.selected || c.kind != Candidate::Kind::Removed) continue;
        removed_gaps.push_back(static_cast<std::uint64_t>(c.baseline_index - previous - 1));
        previous = c.baseline_index;
        removed_at[c.baseline_index + 1] = 1;
      }
      for (std::size_t k = 1; k < removed_at.size(); ++k) removed_at[k] += removed_at[k - 1];
    }
    stream.write_exp_golomb(removed_gaps.size(), 0);
    if (!removed_gaps.empty()) {
      const int order = layout::best_order(removed_gaps);
      stream.write_bits(static_cast<std::uint64_t>(order), layout::kOrderBits);
      for (const std::uint64_t gap : removed_gaps) layout::write_code(stream, gap, order);
    }
    // New entities: id gaps, then each one's absolute state.
    std::vector<const QuantizedEntity*> added;
    {
      std::int64_t previous = -1;
      for (const Candidate& c : candidates) {
        if (!c.selected || c.kind != Candidate::Kind::Added) continue;
        const QuantizedEntity& entity = world[c.world_index];
        added_gaps.push_back(static_cast<std::uint64_t>(entity.id - previous - 1));
        previous = entity.id;
        added.push_back(&entity);
      }
    }
    stream.write_exp_golomb(added.size(), 0);
    if (!added.empty()) {
      const int order = layout::best_order(added_gaps);
      stream.write_bits(static_cast<std::uint64_t>(order), layout::kOrderBits);
      for (std::size_t k = 0; k < added.size(); ++k) {
        layout::write_code(stream, added_gaps[k], order);
        layout::write_absolute(stream, *added[k], widths);
      }
    }
    // Changes, as gaps between indices among the kept baseline entities.
    std::vector<const Candidate*> changed;
    {
      std::int64_t previous = -1;
      for (const Candidate& c : candidates) {
        if (!c.selected || c.kind != Candidate::Kind::Changed) continue;
        const std::int64_t kept_index = c.baseline_index - removed_at[c.baseline_index];
        changed_gaps.push_back(static_cast<std::uint64_t>(kept_index - previous - 1));
        previous = kept_index;
        changed.push_back(&c);
      }
    }
    stream.write_exp_golomb(changed.size(), 0);
    if (!changed.empty()) {
      layout::DeltaOrders chosen = orders;
      chosen.gap = layout::best_order(changed_gaps);
      const std::array<int, layout::kDeltaOrderCount> header_orders{
          chosen.gap,         chosen.velocity[0], chosen.velocity[1], chosen.velocity[2],
          chosen.position[0], chosen.position[1], chosen.position[2], chosen.orientation};
      for (const int order : header_orders) {
        stream.write_bits(static_cast<std::uint64_t>(order), layout::kOrderBits);
      }
      std::uint8_t previous_mask = layout::kInitialFieldMask;
      for (std::size_t k = 0; k < changed.size(); ++k) {
        layout::write_code(stream, changed_gaps[k], chosen.gap);
        layout::write_delta(stream, baseline[changed[k]->baseline_index],
                            world[changed[k]->world_index], chosen, widths, prediction,
                            previous_mask);
      }
    }
    if (header + stream.bytes().size() <= budget_bytes || selected_count == 0) break;
    // Overshoot: drop about as many of the lowest priorities as the excess needs.
    std::size_t excess_bits = (header + stream.bytes().size() - budget_bytes) * 8;
    for (auto k = by_priority.rbegin(); k != by_priority.rend() && excess_bits > 0; ++k) {
      Candidate& c = candidates[*k];
      if (!c.selected) continue;
      c.selected = false;
      --selected_count;
      excess_bits -= std::min<std::size_t>(excess_bits, static_cast<std::size_t>(c.bits));
    }
  }

  // The view the client will hold: the baseline with the sent removals, changes and additions.
  {
    std::vector<std::uint8_t> removed(baseline.size(), 0);
    std::vector<std::int64_t> change_of(baseline.size(), -1);
    std::vector<std::uint32_t> added_indices;
    for (const Candidate& c : candidates) {
      if (!c.selected) continue;
      if (c.kind == Candidate::Kind::Removed) removed[c.baseline_index] = 1;
      if (c.kind == Candidate::Kind::Changed) change_of[c.baseline_index] = c.world_index;
      if (c.kind == Candidate::Kind::Added) added_indices.push_back(c.world_index);
    }
    std::size_t a = 0;
    for (std::size_t k = 0; k < baseline.size(); ++k) {
      if (removed[k]) continue;
      while (a < added_indices.size() && world[added_indices[a]].id < baseline[k].id) {
        next_view_.push_back(world[added_indices[a++]]);
      }
      next_view_.push_back(change_of[k] >= 0 ? world[static_cast<std::size_t>(change_of[k])]
                                             : baseline[k]);
    }
    while (a < added_indices.size()) next_view_.push_back(world[added_indices[a++]]);
  }

  // Priorities: what was sent starts again from zero, what waits keeps its accumulation.
  priority_.clear();
  std::size_t sent = 0;
  for (const Candidate& c : candidates) {
    sent += c.selected;
    if (c.kind == Candidate::Kind::Removed || c.selected) continue;
    priority_.emplace_back(world[c.world_index].id, c.priority);
  }
  std::sort(priority_.begin(), priority_.end());

  out.Clear();
  out.set_tick(tick);
  out.set_baseline_age(baseline_age);
  out.set_entities(stream.bytes().data(), stream.bytes().size());

  Sent& entry = slot(tick);
  entry.valid = true;
  entry.tick = tick;
  entry.view.swap(next_view_);
  has_sent_ = true;
  last_tick_ = tick;

  report_.has_baseline = has_baseline;
  report_.baseline_tick = has_baseline ? acked_tick_ : 0;
  report_.entities = static_cast<std::uint32_t>(world.size());
  report_.pending = static_cast<std::uint32_t>(candidates.size());
  report_.sent = static_cast<std::uint32_t>(sent);
  report_.deferred = static_cast<std::uint32_t>(candidates.size() - sent);
  report_.bytes = out.ByteSizeLong();
}

}  // namespace ricochet::proto
