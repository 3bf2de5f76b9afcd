/// SnapshotEncoder: chooses what to send against the acknowledged baseline, within the budget,
/// and writes the stream (PROTOCOL.md Snapshots §stream): the plain per-client algorithm. The
/// paths that share work between the clients of a tick are in snapshot_encode_cache.cpp.

#include <algorithm>
#include <cassert>
#include <cmath>

#include "ricochet/proto/bit_stream.h"
#include "ricochet/proto/snapshot_codec.h"
#include "snapshot_delta_table.h"
#include "snapshot_encode_pass.h"
#include "snapshot_layout.h"
#include "snapshot_orders.h"

namespace ricochet::proto {

inline void EncodePass::find_pending(std::span<const std::pair<std::uint32_t, float>> carried,
                                     std::array<float, 3> viewer_m) {
  look_from(carried, viewer_m);
  std::size_t i = 0, j = 0;
  while (i < world_.size() || j < baseline_.size()) {
    if (i == world_.size() || (j < baseline_.size() && baseline_[j].id < world_[i].id)) {
      add_removed(j++);
    } else if (j == baseline_.size() || world_[i].id < baseline_[j].id) {
      add_world_candidate(Candidate::Kind::Added, 0, i++, nullptr, kNewEntityChange_m, nullptr);
    } else {
      compare_kept(i, j, baseline_[j]);
      ++i;
      ++j;
    }
  }
}

void EncodePass::estimate_costs() {
  std::size_t changed = 0;
  for (const Candidate& c : candidates_) changed += c.kind == Candidate::Kind::Changed;
  // The orders come from the tally of every changed candidate's delta: the group's tally (every
  // delta of this prediction in the table) without the deltas this client does not use.
  const std::int32_t group = deltas_.group_of(prediction_);
  FieldTallies& tallies = buffers_.tallies;
  if (group >= 0) {
    deltas_.tallies_of_pass(group, pass_, tallies);
  } else {
    tallies = FieldTallies{};
    for (const Candidate& c : candidates_) {
      if (c.kind == Candidate::Kind::Changed) tallies.add(c.way->delta);
    }
  }
  tallies.choose(orders_);

  gap_estimate_ = exp_golomb_bits(changed == 0 ? 0 : baseline_size_ / changed, 0);
  const std::uint64_t orders_key = layout::field_orders_key(orders_);
  for (Candidate& c : candidates_) cost(c, orders_key, gap_estimate_);
}

inline void EncodePass::select(std::size_t budget_bits) {
  // Greedy by priority, highest first, stopping at the first that does not fit: the same as
  // taking everything and leaving out the lowest priorities until the rest fits, which needs
  // the order of only the few left out.
  std::size_t total_bits = 0;
  for (Candidate& c : candidates_) {
    total_bits += static_cast<std::size_t>(c.bits);
    c.selected = true;
  }
  selected_count_ = candidates_.size();
  while (total_bits > budget_bits) total_bits -= static_cast<std::size_t>(drop_lowest().bits);
}

inline void EncodePass::weigh_priorities() {
  std::vector<float>& weights = buffers_.weights;
  if (!viewer_nowhere_) deltas_.distance_weights(viewer_m_, options_.distance_scale_m, weights);
  for (Candidate& c : candidates_) {
    if (c.kind == Candidate::Kind::Removed) continue;
    const float weight = viewer_nowhere_ ? 1.0f : weights[c.world_index];
    c.priority += c.change_m * weight;
  }
}

inline Candidate& EncodePass::drop_lowest() {
  // A heap whose top is the lowest priority, ties broken towards the higher index: priorities
  // are never NaN (distance_weight), so this order is total.
  std::vector<std::pair<float, std::uint32_t>>& heap = buffers_.drop_heap;
  const auto dropped_later = [](const auto& a, const auto& b) {
    return a.first > b.first || (a.first == b.first && a.second < b.second);
  };
  if (!drop_heap_built_) {
    drop_heap_built_ = true;
    weigh_priorities();
    heap.clear();
    for (std::uint32_t k = 0; k < candidates_.size(); ++k) {
      if (candidates_[k].selected) heap.emplace_back(candidates_[k].priority, k);
    }
    std::make_heap(heap.begin(), heap.end(), dropped_later);
  }
  assert(!heap.empty());
  std::pop_heap(heap.begin(), heap.end(), dropped_later);
  Candidate& dropped = candidates_[heap.back().second];
  heap.pop_back();
  dropped.selected = false;
  --selected_count_;
  return dropped;
}

inline bool EncodePass::write(BitWriter& stream, std::size_t stream_budget_bytes) {
  stream.clear();
  // One walk over the candidates (in id order, so in baseline order too) gathers the selected
  // ones of each kind with their gaps: removals between baseline indices, new entities between
  // ids, changes between indices among the kept baseline entities.
  std::vector<std::uint64_t>& removed_gaps = buffers_.removed_gaps;
  std::vector<std::uint64_t>& added_gaps = buffers_.added_gaps;
  std::vector<std::uint64_t>& changed_gaps = buffers_.changed_gaps;
  std::vector<std::uint32_t>& added = buffers_.added;  // world indices
  std::vector<const Candidate*>& changed = buffers_.changed;
  removed_gaps.clear();
  added_gaps.clear();
  changed_gaps.clear();
  added.clear();
  changed.clear();
  {
    std::int64_t previous_removed = -1, previous_added = -1, previous_kept = -1;
    std::int64_t removed_before = 0;  // selected removals of lower baseline index
    for (const Candidate& c : candidates_) {
      if (!c.selected) continue;
      switch (c.kind) {
        case Candidate::Kind::Removed:
          removed_gaps.push_back(
              static_cast<std::uint64_t>(c.baseline_index - previous_removed - 1));
          previous_removed = c.baseline_index;
          ++removed_before;
          break;
        case Candidate::Kind::Added: {
          const std::int64_t id = world_[c.world_index].id;
          added_gaps.push_back(static_cast<std::uint64_t>(id - previous_added - 1));
          previous_added = id;
          added.push_back(c.world_index);
          break;
        }
        case Candidate::Kind::Changed: {
          const std::int64_t kept_index = c.baseline_index - removed_before;
          changed_gaps.push_back(static_cast<std::uint64_t>(kept_index - previous_kept - 1));
          previous_kept = kept_index;
          changed.push_back(&c);
          break;
        }
      }
    }
  }
  stream.write_exp_golomb(removed_gaps.size(), 0);
  if (!removed_gaps.empty()) {
    const int order = layout::best_order(removed_gaps);
    stream.write_bits(static_cast<std::uint64_t>(order), layout::kOrderBits);
    for (const std::uint64_t gap : removed_gaps) layout::write_code(stream, gap, order);
  }
  // New entities: id gaps, each followed by the entity's absolute state.
  stream.write_exp_golomb(added.size(), 0);
  if (!added.empty()) {
    const int order = layout::best_order(added_gaps);
    stream.write_bits(static_cast<std::uint64_t>(order), layout::kOrderBits);
    for (std::size_t k = 0; k < added.size(); ++k) {
      layout::write_code(stream, added_gaps[k], order);
      // Written once per tick, copied to every client the entity is new to.
      const QuantizedEntity& entity = world_[added[k]];
      layout::write_absolute(stream, deltas_.absolute(added[k], entity, widths_));
    }
  }
  // Changes, as gaps between indices among the kept baseline entities.
  stream.write_exp_golomb(changed.size(), 0);
  if (!changed.empty()) {
    layout::DeltaOrders chosen = orders_;
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
      const Candidate& c = *changed[k];
      if (c.body->overflow) {
        layout::write_delta(stream, c.way->delta, chosen, widths_, previous_mask);
      } else {
        layout::write_delta(stream, c.way->delta.mask, *c.body, previous_mask);
      }
    }
  }
  if (stream.bytes().size() <= stream_budget_bytes || selected_count_ == 0) return true;

  // Overshoot: leave out about as many of the lowest priorities as the excess needs.
  std::size_t excess_bits = (stream.bytes().size() - stream_budget_bytes) * 8;
  while (excess_bits > 0 && selected_count_ > 0) {
    excess_bits -= std::min<std::size_t>(excess_bits, static_cast<std::size_t>(drop_lowest().bits));
  }
  return false;
}

inline bool EncodePass::removal_deferred() const {
  return std::any_of(candidates_.begin(), candidates_.end(), [](const Candidate& c) {
    return !c.selected && c.kind == Candidate::Kind::Removed;
  });
}

inline void EncodePass::list_deferred(std::vector<std::uint32_t>& held,
                                      std::vector<QuantizedEntity>& held_states,
                                      std::vector<std::uint32_t>& absent) const {
  held.clear();
  held_states.clear();
  absent.clear();
  for (const Candidate& c : candidates_) {
    if (c.selected) continue;
    if (c.kind == Candidate::Kind::Changed) {
      held.push_back(c.world_index);
      held_states.push_back(*c.then);
    } else {
      absent.push_back(c.world_index);
    }
  }
}

inline void EncodePass::merge_view(std::vector<QuantizedEntity>& view) const {
  assert(baseline_.size() == baseline_size_);
  // Baseline and candidates merged by id: the candidates (in id order) are every difference.
  view.clear();
  std::size_t next = 0;
  const auto new_before = [&](std::uint32_t id) {
    return next < candidates_.size() && candidates_[next].kind == Candidate::Kind::Added &&
           world_[candidates_[next].world_index].id < id;
  };
  for (std::size_t k = 0; k < baseline_.size(); ++k) {
    for (; new_before(baseline_[k].id); ++next) {
      if (candidates_[next].selected) view.push_back(world_[candidates_[next].world_index]);
    }
    if (next < candidates_.size() && candidates_[next].kind != Candidate::Kind::Added &&
        candidates_[next].baseline_index == k) {
      const Candidate& c = candidates_[next++];
      if (c.kind == Candidate::Kind::Changed && c.selected) {
        view.push_back(world_[c.world_index]);
      } else if (!c.selected) {
        view.push_back(baseline_[k]);  // left out: the client keeps its baseline state
      }
    } else {
      view.push_back(baseline_[k]);
    }
  }
  for (; next < candidates_.size(); ++next) {  // new entities after the last baseline one
    assert(candidates_[next].kind == Candidate::Kind::Added);
    if (candidates_[next].selected) view.push_back(world_[candidates_[next].world_index]);
  }
}

inline std::size_t EncodePass::carry_priorities(
    std::vector<std::pair<std::uint32_t, float>>& carried) const {
  // Something was left out only by drop_lowest, which weighed the priorities first.
  carried.clear();
  std::size_t sent = 0;
  for (const Candidate& c : candidates_) {
    sent += c.selected;
    if (c.kind == Candidate::Kind::Removed || c.selected) continue;
    carried.emplace_back(world_[c.world_index].id, c.priority);
  }
  // Candidates follow the world's order, so the ids are increasing already.
  assert(std::is_sorted(carried.begin(), carried.end()));
  return sent;
}

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
    : spec_(spec),
      options_(options),
      ring_(options.ring_size),
      scratch_(std::make_unique<Scratch>(spec_)) {
  assert(spec_.validate().empty() && options_.validate().empty());
}

SnapshotEncoder::SnapshotEncoder(SnapshotEncoder&&) noexcept = default;
SnapshotEncoder& SnapshotEncoder::operator=(SnapshotEncoder&&) noexcept = default;
SnapshotEncoder::~SnapshotEncoder() = default;

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
  encode_with(tick, world, viewer_m, budget_bytes, out, nullptr);
}

void SnapshotEncoder::encode_with(std::uint32_t tick, std::span<const QuantizedEntity> world,
                                  std::array<float, 3> viewer_m, std::size_t budget_bytes,
                                  wire::Snapshot& out, SnapshotEncodeCache* cache) {
  assert(!has_sent_ || tick > last_tick_);
  assert(std::is_sorted(world.begin(), world.end(),
                        [](const auto& a, const auto& b) { return a.id < b.id; }));
  const Baseline baseline = acked_baseline(tick);
  const Budget budget = stream_budget(tick, baseline.age, budget_bytes);
  out.Clear();
  out.set_tick(tick);
  out.set_baseline_age(baseline.age);
  next_held_.clear();
  next_held_states_.clear();
  next_absent_.clear();
  Outcome outcome;
  if (cache) {
    outcome = encode_cached(baseline, tick, world, viewer_m, budget, out, *cache);
  } else {
    scratch_->deltas.reset(world, spec_);
    outcome = encode_against(baseline, scratch_->deltas, world, viewer_m, budget, out);
  }
  remember_sent(tick, world, outcome);

  report_.has_baseline = baseline.exists;
  report_.baseline_tick = baseline.exists ? acked_tick_ : 0;
  report_.entities = static_cast<std::uint32_t>(world.size());
  report_.pending = static_cast<std::uint32_t>(outcome.pending);
  report_.sent = static_cast<std::uint32_t>(outcome.sent);
  report_.deferred = static_cast<std::uint32_t>(outcome.pending - outcome.sent);
  report_.bytes = out.ByteSizeLong();
}

SnapshotEncoder::Baseline SnapshotEncoder::acked_baseline(std::uint32_t tick) {
  // The newest acknowledged snapshot, while the ring still holds it; either a view of the
  // client's own or a world but for exceptions.
  const Sent& acked = slot(acked_tick_);
  Baseline baseline;
  baseline.exists = has_ack_ && acked.valid && acked.tick == acked_tick_;
  if (!baseline.exists) return baseline;
  baseline.age = tick - acked_tick_;
  baseline.is_world = acked.world_token != 0;
  if (baseline.is_world) {
    baseline.world = {*acked.world, acked.held, acked.held_states, acked.absent};
    baseline.world_token = acked.world_token;
    baseline.size = baseline.world.world.size() - baseline.world.absent.size();
  } else {
    baseline.view = acked.view;
    baseline.size = acked.view.size();
  }
  return baseline;
}

SnapshotEncoder::Budget SnapshotEncoder::stream_budget(std::uint32_t tick,
                                                       std::uint32_t baseline_age,
                                                       std::size_t budget_bytes) {
  const std::size_t header = header_bytes(tick, baseline_age, budget_bytes);
  Budget budget;
  budget.stream_bytes = budget_bytes > header ? budget_bytes - header : 0;
  // Counts, orders and padding come before any entity.
  const std::size_t fixed_bits = 3 + (2 + layout::kDeltaOrderCount) * layout::kOrderBits + 8;
  budget.select_bits =
      budget.stream_bytes * 8 > fixed_bits ? budget.stream_bytes * 8 - fixed_bits : 0;
  return budget;
}

SnapshotEncoder::Outcome SnapshotEncoder::encode_against(
    const Baseline& baseline, DeltaTable& deltas, std::span<const QuantizedEntity> world,
    std::array<float, 3> viewer_m, const Budget& budget, wire::Snapshot& out) {
  // A baseline that is a world the cache saw is that world made whole.
  std::span<const QuantizedEntity> view = baseline.view;
  if (baseline.is_world) {
    hold(baseline.world, scratch_->baseline);
    view = scratch_->baseline;
  }
  EncodePass pass(spec_, options_, view, baseline.size, baseline.age, world, scratch_->widths,
                  scratch_->buffers, deltas);
  pass.find_pending(priority_, viewer_m);
  pass.estimate_costs();
  return finish(pass, baseline, budget, out);
}

SnapshotEncoder::Outcome SnapshotEncoder::finish(EncodePass& pass, const Baseline& baseline,
                                                 const Budget& budget, wire::Snapshot& out) {
  pass.select(budget.select_bits);
  bool fits = false;
  while (!fits) fits = pass.write(stream_, budget.stream_bytes);  // each miss leaves some out
  Outcome outcome;
  if (pass.removal_deferred()) {
    if (!pass.has_whole_baseline()) {  // followed a walk: make the baseline whole
      hold(baseline.world, scratch_->baseline);
      pass.use_baseline(scratch_->baseline);
    }
    pass.merge_view(next_view_);
    outcome.world_but_exceptions = false;
  } else {
    pass.list_deferred(next_held_, next_held_states_, next_absent_);
  }
  outcome.pending = pass.pending();
  outcome.sent = pass.carry_priorities(priority_);
  // Everything sent means the first write fitted (a miss leaves something out).
  if (outcome.sent == outcome.pending) outcome.candidate_bits = pass.candidate_bits();
  assign_bytes(*out.mutable_entities(), stream_.bytes());
  return outcome;
}

void SnapshotEncoder::remember_sent(std::uint32_t tick, std::span<const QuantizedEntity> world,
                                    Outcome& outcome) {
  // What the client will hold; this may overwrite the baseline's slot, used no more. Unless it
  // holds the cache's copy of the world, the view is the client's own.
  const bool holds_shared_world = outcome.world_but_exceptions && outcome.world_token != 0;
  if (outcome.world_but_exceptions && !holds_shared_world) {
    hold({world, next_held_, next_held_states_, next_absent_}, next_view_);
  }
  Sent& entry = slot(tick);
  entry.valid = true;
  entry.tick = tick;
  entry.world_token = holds_shared_world ? outcome.world_token : 0;
  entry.world = holds_shared_world ? std::move(outcome.shared_world) : nullptr;
  if (holds_shared_world) {
    entry.view.clear();
  } else {
    entry.view.swap(next_view_);
  }
  entry.held.swap(next_held_);
  entry.held_states.swap(next_held_states_);
  entry.absent.swap(next_absent_);
  has_sent_ = true;
  last_tick_ = tick;
}

}  // namespace ricochet::proto
