/// SnapshotEncoder: chooses what to send against the acknowledged baseline, within the budget,
/// and writes the stream (PROTOCOL.md Snapshots §stream).

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>
#include <optional>

#include "ricochet/proto/bit_stream.h"
#include "ricochet/proto/snapshot_codec.h"
#include "snapshot_delta_table.h"
#include "snapshot_layout.h"
#include "snapshot_orders.h"

namespace ricochet::proto {

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

/// Copies `bytes` into a protobuf bytes field, keeping its capacity (the iterator form of
/// assign copies one char at a time).
void assign_bytes(std::string& field, const std::vector<std::uint8_t>& bytes) {
  field.assign(reinterpret_cast<const char*>(bytes.data()), bytes.size());
}

/// An entity that differs from the baseline: gone, new or changed.
struct Candidate {
  enum class Kind : std::uint8_t { Removed, Added, Changed };
  Kind kind = Kind::Changed;
  bool selected = false;
  std::uint32_t baseline_index = 0;  ///< Removed, Changed
  std::uint32_t world_index = 0;     ///< Added, Changed
  /// What it carried from before, until weigh_priorities adds this tick's change at its distance.
  float priority = 0;
  float change_m = 0;                     ///< Added, Changed: this tick's change (PROTOCOL.md §8)
  int bits = 0;                           ///< estimate, for the budget
  DeltaTable::Way* way = nullptr;         ///< Changed: its delta
  const QuantizedEntity* then = nullptr;  ///< Changed: the client's baseline state
  /// Changed: its fields written with this encode's orders (estimate_costs).
  const layout::DeltaBody* body = nullptr;
};

/// A baseline as a world the SnapshotEncodeCache saw, but for the few entities the client holds
/// at older states or not at all (SnapshotEncoder::Sent), by their indices in that world.
struct WorldBaseline {
  std::span<const QuantizedEntity> world;
  std::span<const std::uint32_t> held;           ///< sorted
  std::span<const QuantizedEntity> held_states;  ///< the client's, one per `held`
  std::span<const std::uint32_t> absent;         ///< sorted
};

/// The entities a client holds whose baseline is `baseline`: its world with the held entities
/// at their older states and the absent ones left out.
void hold(const WorldBaseline& baseline, std::vector<QuantizedEntity>& view) {
  view.clear();
  std::size_t h = 0, a = 0;
  for (std::uint32_t k = 0; k < baseline.world.size(); ++k) {
    if (a < baseline.absent.size() && baseline.absent[a] == k) {
      ++a;
    } else if (h < baseline.held.size() && baseline.held[h] == k) {
      view.push_back(baseline.held_states[h++]);
    } else {
      view.push_back(baseline.world[k]);
    }
  }
}

/// One step of the walk of a tick's world against an earlier world by id.
struct WalkStep {
  enum class Kind : std::uint8_t { Removed, Added, Kept };
  Kind kind = Kind::Kept;
  std::uint32_t baseline_index = 0;  ///< Removed, Kept: in the earlier world
  std::uint32_t world_index = 0;     ///< Added, Kept
  /// Kept: its delta when the entity changed (while way->stamp == stamp), else null.
  DeltaTable::Way* way = nullptr;
  std::uint64_t stamp = 0;
};

/// The walk of one tick's world against the world a baseline token names, at one prediction:
/// worked out once per tick, then followed by every client whose baseline is that world.
struct SharedWalk {
  std::uint64_t baseline_token = 0;
  layout::Prediction prediction;
  std::vector<WalkStep> steps;
  /// What find_pending and estimate_costs give a follower holding the whole world (no
  /// exceptions), worked out once, for every later follower to start from.
  struct WholeWorldStart {
    bool valid = false;
    std::vector<Candidate> candidates;  ///< with nothing carried in their priorities
    std::vector<std::uint64_t> stamps;  ///< per candidate, a changed one's way's stamp
    /// Per index of the walk's earlier world: its candidate, or -1; its world index, or -1
    /// when it was removed.
    std::vector<std::int32_t> candidate_of, world_of;
    FieldTallies tallies;  ///< of the changed candidates' deltas
    std::size_t changed = 0;
    int gap_estimate = 0;  ///< in the changed candidates' bits
    layout::DeltaOrders orders;
    std::uint64_t orders_key = 0;
    std::uint64_t replaced = 0;  ///< DeltaTable::replaced() when kept
  } whole_world_start;
};

/// One of a client's exceptions, as take_start edits the walk's start with it (W: the walk's
/// earlier world).
struct StartEdit {
  std::uint32_t k = 0;  ///< index in W
  std::uint32_t id = 0;
  bool absent = false;             ///< else held
  std::int32_t start_index = -1;   ///< the start's candidate for it
  std::int32_t world_index = -1;   ///< -1: removed
  DeltaTable::Way* way = nullptr;  ///< held and changed: its delta
  const QuantizedEntity* then = nullptr;
};

/// The buffers of one encode (SnapshotEncoder::Scratch holds them between encodes).
struct EncodeBuffers {
  std::vector<Candidate> candidates;
  std::vector<std::pair<float, std::uint32_t>> drop_heap;  ///< drop_lowest's
  std::vector<float> weights;                              ///< weigh_priorities': per world entity
  std::vector<StartEdit> edits;                            ///< take_start's
  FieldTallies tallies;                                    ///< estimate_costs'
  std::vector<std::uint64_t> removed_gaps, added_gaps, changed_gaps;  ///< write's
  std::vector<std::uint32_t> added;
  std::vector<const Candidate*> changed;
};

/// One encode: the baseline and the world, what differs, what goes in, the stream and the view
/// the client will hold. Each step is one method; SnapshotEncoder::encode calls them in order.
class EncodePass {
 public:
  /// baseline: the client's entities, or empty when it is a world but for exceptions, whose
  /// walk find_pending follows (then of baseline_size entities).
  EncodePass(const QuantizationSpec& spec, const SnapshotEncoderOptions& options,
             std::span<const QuantizedEntity> baseline, std::size_t baseline_size,
             std::uint32_t baseline_age, std::span<const QuantizedEntity> world,
             const layout::FieldWidths& widths, EncodeBuffers& buffers, DeltaTable& deltas)
      : spec_(spec),
        options_(options),
        baseline_(baseline),
        baseline_size_(baseline_size),
        world_(world),
        widths_(widths),
        prediction_(layout::make_prediction(baseline_age, spec)),
        buffers_(buffers),
        candidates_(buffers.candidates),
        deltas_(deltas),
        pass_(deltas.begin_pass()) {
    candidates_.clear();
  }

  /// Walks world and baseline by id; each difference becomes a candidate whose priority adds
  /// this tick's weight to what it carried (`carried`, sorted by id), a changed one with its
  /// delta.
  void find_pending(std::span<const std::pair<std::uint32_t, float>> carried,
                    std::array<float, 3> viewer_m);
  /// The same for a baseline that is the whole world `walk` was recorded against, `earlier`:
  /// follows the walk.
  void find_pending(std::span<const std::pair<std::uint32_t, float>> carried,
                    std::array<float, 3> viewer_m, const SharedWalk& walk,
                    std::span<const QuantizedEntity> earlier);
  /// Records the walk of the world against `earlier` (a world the cache saw) into `walk`, with
  /// the delta of every changed entity.
  void record_walk(std::span<const QuantizedEntity> earlier, SharedWalk& walk);
  /// Chooses the field orders over all candidates and estimates each candidate's bits.
  void estimate_costs();
  /// Keeps what find_pending and estimate_costs found for a follower of `walk` holding the
  /// whole world, for the followers after it.
  void keep_start(const SharedWalk& walk, SharedWalk::WholeWorldStart& start) const;
  /// Instead of find_pending and estimate_costs for a follower of the walk: the kept start
  /// edited at the client's exceptions, with its carried priorities, the orders of its own
  /// tally (the start's less the deltas the exceptions take out, plus theirs), and the start's
  /// bits where those orders are the start's and the deltas and bodies are what they were.
  void take_start(const SharedWalk::WholeWorldStart& start, const WorldBaseline& baseline,
                  std::span<const std::pair<std::uint32_t, float>> carried,
                  std::array<float, 3> viewer_m);
  /// Selects everything that fits budget_bits by priority, highest first.
  void select(std::size_t budget_bits);
  /// Writes the selected candidates; false if the stream exceeds stream_budget_bytes, after
  /// leaving out about as many of the lowest priorities as the excess needs (call again).
  bool write(BitWriter& stream, std::size_t stream_budget_bytes);
  /// Whether a removal was left out (practically never: removals go first). Otherwise the
  /// client holds the world after decoding the stream but for the deferred entities.
  bool removal_deferred() const;
  /// The deferred entities by world index: `held` (changed: the client keeps `held_states`,
  /// their baseline states) and `absent` (new: not held at all).
  void list_deferred(std::vector<std::uint32_t>& held, std::vector<QuantizedEntity>& held_states,
                     std::vector<std::uint32_t>& absent) const;
  /// The entity set the client holds after decoding the stream, merged from the baseline
  /// (which must be whole: use_baseline) and the candidates.
  void merge_view(std::vector<QuantizedEntity>& view) const;
  /// The client's whole baseline, for merge_view after following a walk.
  void use_baseline(std::span<const QuantizedEntity> baseline) { baseline_ = baseline; }
  /// Deferred entities' priorities, sorted by id; returns how many candidates were sent.
  std::size_t carry_priorities(std::vector<std::pair<std::uint32_t, float>>& carried) const;
  std::size_t pending() const { return candidates_.size(); }
  /// estimate_costs' bits of every candidate, summed.
  std::size_t candidate_bits() const {
    std::size_t bits = 0;
    for (const Candidate& c : candidates_) bits += static_cast<std::size_t>(c.bits);
    return bits;
  }

 private:
  /// Unselects the selected candidate of lowest priority (of equal ones, the last) and
  /// returns it; the first call orders the selected candidates, which must not be empty.
  Candidate& drop_lowest();
  /// Sets a candidate's bits for the orders_ (whose key is orders_key) and a gap estimate.
  void cost(Candidate& c, std::uint64_t orders_key, int gap_estimate);
  /// What the client carried for the entity `id`; ids must increase from call to call.
  float carried_priority(std::uint32_t id);
  /// Adds each candidate's change at its distance to what it carried: only an encode that
  /// leaves something out needs its priorities.
  void weigh_priorities();
  /// What find_pending weighs candidates by: the priorities carried from before and the viewer.
  void look_from(std::span<const std::pair<std::uint32_t, float>> carried,
                 std::array<float, 3> viewer_m);
  double change_m(const QuantizedEntity& then, const QuantizedEntity& now) const;
  /// The delta of world entity i from `then`, found or claimed.
  DeltaTable::Way& delta_of(std::size_t i, const QuantizedEntity& then);
  /// Adds a candidate for world entity i with what it carried and its `change` (weighed by
  /// distance only if something is left out); carried_next_ follows the carried priorities,
  /// which ids increase through.
  void add_world_candidate(Candidate::Kind kind, std::size_t j, std::size_t i, DeltaTable::Way* way,
                           double change, const QuantizedEntity* then);
  void add_removed(std::size_t j);
  /// Baseline entity j, `then`, still in the world at i: a candidate with its delta when it
  /// changed.
  void compare_kept(std::size_t i, std::size_t j, const QuantizedEntity& then);

  const QuantizationSpec& spec_;
  const SnapshotEncoderOptions& options_;
  std::span<const QuantizedEntity> baseline_;
  std::size_t baseline_size_;
  std::span<const QuantizedEntity> world_;
  const layout::FieldWidths& widths_;
  layout::Prediction prediction_;
  layout::DeltaOrders orders_;
  EncodeBuffers& buffers_;
  std::vector<Candidate>& candidates_;
  std::size_t selected_count_ = 0;
  bool drop_heap_built_ = false;  ///< buffers_.drop_heap holds the selected candidates
  std::span<const std::pair<std::uint32_t, float>> carried_;  ///< find_pending's
  std::size_t carried_next_ = 0;
  bool viewer_nowhere_ = false;
  std::array<float, 3> viewer_m_{};
  DeltaTable& deltas_;    ///< the encoder's own, or the tick's shared one
  std::uint64_t pass_;    ///< marks the deltas this pass takes
  int gap_estimate_ = 0;  ///< estimate_costs'
};

double EncodePass::change_m(const QuantizedEntity& then, const QuantizedEntity& now) const {
  double moved_m = 0, velocity_mps = 0;
  for (int a = 0; a < 3; ++a) {
    moved_m +=
        std::fabs(static_cast<double>(now.position[a]) - then.position[a]) * spec_.position_step_m;
    velocity_mps += std::fabs(static_cast<double>(now.velocity[a]) - then.velocity[a]) *
                    spec_.velocity_step_mps;
  }
  const bool turned =
      then.orientation_largest != now.orientation_largest || then.orientation != now.orientation;
  return kMinimumChange_m + moved_m + velocity_mps * kVelocityHorizon_s +
         (turned ? kOrientationChange_m : 0) + (then.flags != now.flags ? kFlagsChange_m : 0);
}

DeltaTable::Way& EncodePass::delta_of(std::size_t i, const QuantizedEntity& then) {
  if (DeltaTable::Way* way = deltas_.find(i, then, prediction_)) return *way;
  return deltas_.claim(i, then, world_[i], widths_, prediction_, change_m(then, world_[i]));
}

void EncodePass::add_world_candidate(Candidate::Kind kind, std::size_t j, std::size_t i,
                                     DeltaTable::Way* way, double change,
                                     const QuantizedEntity* then) {
  candidates_.push_back({.kind = kind,
                         .baseline_index = static_cast<std::uint32_t>(j),
                         .world_index = static_cast<std::uint32_t>(i),
                         .priority = carried_priority(world_[i].id),
                         .change_m = static_cast<float>(change),
                         .way = way,
                         .then = then});
}

float EncodePass::carried_priority(std::uint32_t id) {
  std::size_t& p = carried_next_;
  while (p < carried_.size() && carried_[p].first < id) ++p;
  return p < carried_.size() && carried_[p].first == id ? carried_[p].second : 0;
}

void EncodePass::look_from(std::span<const std::pair<std::uint32_t, float>> carried,
                           std::array<float, 3> viewer_m) {
  carried_ = carried;
  // A viewer nowhere (NaN or infinite) sees everything as near, so priorities stay ordered.
  viewer_nowhere_ =
      !std::isfinite(viewer_m[0]) || !std::isfinite(viewer_m[1]) || !std::isfinite(viewer_m[2]);
  viewer_m_ = viewer_m;
  candidates_.reserve(world_.size() + baseline_size_);
}

void EncodePass::add_removed(std::size_t j) {
  candidates_.push_back({.kind = Candidate::Kind::Removed,
                         .baseline_index = static_cast<std::uint32_t>(j),
                         .priority = kRemovalPriority});
}

void EncodePass::compare_kept(std::size_t i, std::size_t j, const QuantizedEntity& then) {
  if (same_state(world_[i], then)) return;
  DeltaTable::Way& way = delta_of(i, then);
  way.used_by = pass_;
  add_world_candidate(Candidate::Kind::Changed, j, i, &way, way.change_m, &then);
}

void EncodePass::find_pending(std::span<const std::pair<std::uint32_t, float>> carried,
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

void EncodePass::record_walk(std::span<const QuantizedEntity> earlier, SharedWalk& walk) {
  walk.steps.clear();
  std::size_t i = 0, k = 0;
  while (i < world_.size() || k < earlier.size()) {
    WalkStep& step = walk.steps.emplace_back();
    if (i == world_.size() || (k < earlier.size() && earlier[k].id < world_[i].id)) {
      step.kind = WalkStep::Kind::Removed;
      step.baseline_index = static_cast<std::uint32_t>(k++);
    } else if (k == earlier.size() || world_[i].id < earlier[k].id) {
      step.kind = WalkStep::Kind::Added;
      step.world_index = static_cast<std::uint32_t>(i++);
    } else {
      step.kind = WalkStep::Kind::Kept;
      step.baseline_index = static_cast<std::uint32_t>(k);
      step.world_index = static_cast<std::uint32_t>(i);
      if (!same_state(world_[i], earlier[k])) {
        step.way = &delta_of(i, earlier[k]);
        step.stamp = step.way->stamp;
      }
      ++i;
      ++k;
    }
  }
}

void EncodePass::find_pending(std::span<const std::pair<std::uint32_t, float>> carried,
                              std::array<float, 3> viewer_m, const SharedWalk& walk,
                              std::span<const QuantizedEntity> earlier) {
  look_from(carried, viewer_m);
  for (const WalkStep& step : walk.steps) {
    switch (step.kind) {
      case WalkStep::Kind::Added:
        add_world_candidate(Candidate::Kind::Added, 0, step.world_index, nullptr,
                            kNewEntityChange_m, nullptr);
        break;
      case WalkStep::Kind::Removed:
        add_removed(step.baseline_index);
        break;
      case WalkStep::Kind::Kept:
        if (step.way && step.way->stamp == step.stamp) {
          step.way->used_by = pass_;
          add_world_candidate(Candidate::Kind::Changed, step.baseline_index, step.world_index,
                              step.way, step.way->change_m, &earlier[step.baseline_index]);
        } else if (step.way) {
          // Its way since given to another delta.
          compare_kept(step.world_index, step.baseline_index, earlier[step.baseline_index]);
        }
        break;
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

void EncodePass::cost(Candidate& c, std::uint64_t orders_key, int gap_estimate) {
  switch (c.kind) {
    case Candidate::Kind::Changed: {
      // Written once per orders: write copies these bits, and so may other clients' encodes.
      c.body = &deltas_.body(*c.way, orders_, orders_key, widths_);
      c.bits = (c.body->overflow ? layout::delta_bits(c.way->delta, orders_, widths_)
                                 : layout::kMaskEstimateBits + c.body->bits) +
               gap_estimate;
      break;
    }
    case Candidate::Kind::Removed:
      c.bits = 2 * bits_for_count(baseline_size_ + 1) + 1;
      break;
    case Candidate::Kind::Added: {
      // The state's bits, written once per tick for every client the entity is new to.
      const layout::AbsoluteBody& body =
          deltas_.absolute(c.world_index, world_[c.world_index], widths_);
      c.bits = body.head.bits + body.tail.bits + 2 * bits_for_count(world_.size() + 1) + 1;
      break;
    }
  }
}

void EncodePass::keep_start(const SharedWalk& walk, SharedWalk::WholeWorldStart& start) const {
  start.valid = true;
  start.candidates.assign(candidates_.begin(), candidates_.end());
  start.stamps.resize(candidates_.size());
  start.candidate_of.assign(baseline_size_, -1);
  start.world_of.assign(baseline_size_, -1);
  start.changed = 0;
  for (std::size_t n = 0; n < start.candidates.size(); ++n) {
    Candidate& c = start.candidates[n];
    if (c.kind != Candidate::Kind::Removed) c.priority = 0;
    if (c.kind != Candidate::Kind::Added)
      start.candidate_of[c.baseline_index] = static_cast<std::int32_t>(n);
    if (c.kind == Candidate::Kind::Changed) {
      start.stamps[n] = c.way->stamp;
      c.bits -= gap_estimate_;
      ++start.changed;
    }
  }
  for (const WalkStep& step : walk.steps) {
    if (step.kind == WalkStep::Kind::Kept) {
      start.world_of[step.baseline_index] = static_cast<std::int32_t>(step.world_index);
    }
  }
  start.tallies = buffers_.tallies;
  start.gap_estimate = gap_estimate_;
  start.orders = orders_;
  start.orders_key = layout::field_orders_key(orders_);
  start.replaced = deltas_.replaced();
}

void EncodePass::take_start(const SharedWalk::WholeWorldStart& start, const WorldBaseline& baseline,
                            std::span<const std::pair<std::uint32_t, float>> carried,
                            std::array<float, 3> viewer_m) {
  candidates_.clear();  // the buffers may hold the start's own pass
  look_from(carried, viewer_m);
  // Nothing replaced since the start was kept: its deltas and bodies are what they were.
  const bool as_kept = deltas_.replaced() == start.replaced;
  if (as_kept && baseline.held.empty() && baseline.absent.empty()) {
    // The whole world: the start as it is, with this client's carried priorities.
    candidates_.assign(start.candidates.begin(), start.candidates.end());
    orders_ = start.orders;
    gap_estimate_ = start.gap_estimate;
    for (Candidate& c : candidates_) {
      if (c.kind == Candidate::Kind::Changed) c.bits += gap_estimate_;
      if (c.kind != Candidate::Kind::Removed && carried_next_ < carried_.size()) {
        c.priority = carried_priority(world_[c.world_index].id);
      }
    }
    return;
  }
  // A start candidate's way, claimed again if it has since been given to another delta (the
  // same baseline state and world state give the same delta).
  const auto way_of = [&](std::size_t n) -> DeltaTable::Way& {
    const Candidate& c = start.candidates[n];
    if (as_kept || c.way->stamp == start.stamps[n]) return *c.way;
    return delta_of(c.world_index, *c.then);
  };

  // The exceptions' edits, in W's order, and the tally and changed count they leave.
  FieldTallies& tallies = buffers_.tallies;
  tallies = start.tallies;
  std::size_t changed = start.changed;
  std::vector<StartEdit>& edits = buffers_.edits;
  edits.clear();
  std::size_t h = 0, a = 0;
  while (h < baseline.held.size() || a < baseline.absent.size()) {
    StartEdit edit;
    edit.absent = h == baseline.held.size() ||
                  (a < baseline.absent.size() && baseline.absent[a] < baseline.held[h]);
    edit.k = edit.absent ? baseline.absent[a] : baseline.held[h];
    edit.id = baseline.world[edit.k].id;
    edit.start_index = start.candidate_of[edit.k];
    edit.world_index = start.world_of[edit.k];
    if (edit.start_index >= 0 &&
        start.candidates[static_cast<std::size_t>(edit.start_index)].kind ==
            Candidate::Kind::Changed) {
      tallies.remove(way_of(static_cast<std::size_t>(edit.start_index)).delta);
      --changed;
    }
    if (!edit.absent && edit.world_index >= 0) {
      const QuantizedEntity& then = baseline.held_states[h];
      const auto i = static_cast<std::size_t>(edit.world_index);
      if (!same_state(world_[i], then)) {
        edit.way = &delta_of(i, then);
        edit.then = &then;
        tallies.add(edit.way->delta);
        ++changed;
      }
    }
    edit.absent ? ++a : ++h;
    edits.push_back(edit);
  }
  tallies.choose(orders_);
  const std::uint64_t orders_key = layout::field_orders_key(orders_);
  const bool start_orders = orders_key == start.orders_key;
  gap_estimate_ = exp_golomb_bits(changed == 0 ? 0 : baseline_size_ / changed, 0);

  // The start's candidates in id order with the edits in their places; a baseline index counts
  // only the entities the client holds.
  std::size_t absent_before = 0;
  const auto apply = [&](const StartEdit& edit) {
    const std::size_t j = edit.k - absent_before;
    if (edit.absent) {
      if (edit.world_index >= 0) {
        add_world_candidate(Candidate::Kind::Added, 0, static_cast<std::size_t>(edit.world_index),
                            nullptr, kNewEntityChange_m, nullptr);
        cost(candidates_.back(), orders_key, gap_estimate_);
      }
      ++absent_before;
    } else if (edit.world_index < 0) {
      add_removed(j);
      cost(candidates_.back(), orders_key, gap_estimate_);
    } else if (edit.way) {
      add_world_candidate(Candidate::Kind::Changed, j, static_cast<std::size_t>(edit.world_index),
                          edit.way, edit.way->change_m, edit.then);
      cost(candidates_.back(), orders_key, gap_estimate_);
    }
  };
  std::size_t e = 0;
  for (std::size_t n = 0; n < start.candidates.size(); ++n) {
    const Candidate& from = start.candidates[n];
    const std::uint32_t id = from.kind == Candidate::Kind::Removed
                                 ? baseline.world[from.baseline_index].id
                                 : world_[from.world_index].id;
    while (e < edits.size() && edits[e].id < id) apply(edits[e++]);
    if (e < edits.size() && edits[e].id == id) {
      apply(edits[e++]);
      continue;
    }
    Candidate& c = candidates_.emplace_back(from);
    switch (c.kind) {
      case Candidate::Kind::Removed:
        c.baseline_index -= static_cast<std::uint32_t>(absent_before);
        cost(c, orders_key, gap_estimate_);
        break;
      case Candidate::Kind::Added:
        c.priority = carried_priority(id);
        break;
      case Candidate::Kind::Changed:
        c.baseline_index -= static_cast<std::uint32_t>(absent_before);
        c.priority = carried_priority(id);
        c.way = &way_of(n);
        if (start_orders && (as_kept || (c.way == from.way && c.way->stamp == start.stamps[n] &&
                                         deltas_.find_body(*c.way, orders_key) == c.body))) {
          c.bits += gap_estimate_;
        } else {
          cost(c, orders_key, gap_estimate_);
        }
        break;
    }
  }
  while (e < edits.size()) apply(edits[e++]);
}

void EncodePass::select(std::size_t budget_bits) {
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

void EncodePass::weigh_priorities() {
  std::vector<float>& weights = buffers_.weights;
  if (!viewer_nowhere_) deltas_.distance_weights(viewer_m_, options_.distance_scale_m, weights);
  for (Candidate& c : candidates_) {
    if (c.kind == Candidate::Kind::Removed) continue;
    const float weight = viewer_nowhere_ ? 1.0f : weights[c.world_index];
    c.priority += c.change_m * weight;
  }
}

Candidate& EncodePass::drop_lowest() {
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

bool EncodePass::write(BitWriter& stream, std::size_t stream_budget_bytes) {
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

bool EncodePass::removal_deferred() const {
  return std::any_of(candidates_.begin(), candidates_.end(), [](const Candidate& c) {
    return !c.selected && c.kind == Candidate::Kind::Removed;
  });
}

void EncodePass::list_deferred(std::vector<std::uint32_t>& held,
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

void EncodePass::merge_view(std::vector<QuantizedEntity>& view) const {
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

std::size_t EncodePass::carry_priorities(
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

}  // namespace

/// One stream a cache holds: what an encode wrote when everything pending was sent, against a
/// baseline that was itself a whole world the cache saw (or no baseline), and what another
/// encode of the same tick against the same baseline and age needs to write the same.
struct SharedStream {
  /// The baseline's world token (SnapshotEncoder::Sent::world_token); 0 for no baseline.
  std::uint64_t baseline_token = 0;
  std::uint32_t baseline_age = 0;
  layout::Prediction prediction;
  std::size_t candidate_bits = 0;  ///< the estimates of every pending entity, summed
  std::uint32_t pending = 0;
  std::vector<std::uint8_t> stream;
};

/// Tokens naming a world a cache saw, unique in the process so that views of different caches
/// (or of a cache since destroyed) never match.
std::uint64_t next_world_token() {
  static std::atomic<std::uint64_t> last{0};
  return last.fetch_add(1, std::memory_order_relaxed) + 1;
}

struct SnapshotEncodeCache::Streams {
  bool has_tick = false;
  std::uint32_t tick = 0;
  std::optional<layout::FieldWidths> widths;  ///< of the encoders sharing this tick
  std::size_t used = 0;                       ///< of entries, this tick's
  std::size_t next_replaced = 0;              ///< when all are used
  std::vector<SharedStream> entries;
  /// Copies of this and earlier ticks' worlds, held by the clients left holding them
  /// (SnapshotEncoder::Sent::world); one no client holds any more is reused.
  std::vector<std::shared_ptr<std::vector<QuantizedEntity>>> worlds;
  std::shared_ptr<const std::vector<QuantizedEntity>> world_now;  ///< this tick's copy
  /// This tick's walks against the worlds of baseline tokens, as many as entries.
  std::size_t walks_used = 0;
  std::size_t next_walk_replaced = 0;
  std::vector<SharedWalk> walks;
  const QuantizedEntity* world = nullptr;  ///< this tick's, its identity
  std::size_t world_size = 0;
  /// Names this tick's world: a client sent all of it holds a view equal to it, and two views
  /// with one token are equal without comparing them.
  std::uint64_t world_token = 0;
  DeltaTable deltas;

  explicit Streams(std::size_t max_streams) : entries(max_streams), walks(max_streams) {}

  /// Forgets the previous tick's streams when `tick` is a new one.
  void begin(std::uint32_t tick_now, std::span<const QuantizedEntity> world_now,
             const layout::FieldWidths& encoder_widths, const QuantizationSpec& spec,
             const SnapshotCacheLayers& layers) {
    if (has_tick && tick == tick_now && world == world_now.data() &&
        world_size == world_now.size() && widths == encoder_widths) {
      return;
    }
    has_tick = true;
    tick = tick_now;
    world = world_now.data();
    world_size = world_now.size();
    widths = encoder_widths;
    world_token = next_world_token();
    this->world_now = copy_of(world_now);
    used = 0;
    next_replaced = 0;
    walks_used = 0;
    next_walk_replaced = 0;
    if (layers.deltas) deltas.reset(world_now, spec);
  }

  const SharedStream* find(std::uint64_t baseline_token, std::uint32_t baseline_age,
                           const layout::Prediction& prediction) const {
    for (std::size_t k = 0; k < used; ++k) {
      const SharedStream& entry = entries[k];
      if (entry.baseline_token == baseline_token && entry.baseline_age == baseline_age &&
          entry.prediction == prediction) {
        return &entry;
      }
    }
    return nullptr;
  }

  /// This tick's walk against the world of `baseline_token` at `prediction`, or null.
  SharedWalk* find_walk(std::uint64_t baseline_token, const layout::Prediction& prediction) {
    for (std::size_t k = 0; k < walks_used; ++k) {
      if (walks[k].baseline_token == baseline_token && walks[k].prediction == prediction) {
        return &walks[k];
      }
    }
    return nullptr;
  }
  SharedWalk& claim_walk(std::uint64_t baseline_token, const layout::Prediction& prediction) {
    SharedWalk& walk = claim_slot(walks, walks_used, next_walk_replaced);
    walk.baseline_token = baseline_token;
    walk.prediction = prediction;
    walk.whole_world_start.valid = false;
    return walk;
  }
  /// A copy of `world` in a vector no client holds any more, or a new one.
  std::shared_ptr<const std::vector<QuantizedEntity>> copy_of(
      std::span<const QuantizedEntity> world) {
    // Each copy is held here and by the clients holding it: a count of 1 is here alone. The
    // previous tick's copy (world_now) counts too, so it is never the one reused.
    auto unheld = std::find_if(worlds.begin(), worlds.end(),
                               [](const auto& copy) { return copy.use_count() == 1; });
    if (unheld == worlds.end()) {
      unheld = worlds.insert(worlds.end(), std::make_shared<std::vector<QuantizedEntity>>());
    }
    (*unheld)->assign(world.begin(), world.end());
    return *unheld;
  }

  SharedStream& claim() { return claim_slot(entries, used, next_replaced); }

  /// The next unused of `slots` this tick, else the one used longest ago.
  template <typename Slot>
  static Slot& claim_slot(std::vector<Slot>& slots, std::size_t& used, std::size_t& next_replaced) {
    if (used < slots.size()) return slots[used++];
    Slot& slot = slots[next_replaced];
    next_replaced = (next_replaced + 1) % slots.size();
    return slot;
  }
};

SnapshotEncodeCache::SnapshotEncodeCache(SnapshotCacheLayers layers, std::size_t max_streams)
    : streams_(std::make_unique<Streams>(std::clamp<std::size_t>(max_streams, 1, 64))),
      layers_(layers) {
  // A layer works only on top of those it needs.
  layers_.walks = layers_.walks && layers_.deltas;
  layers_.whole_world_start = layers_.whole_world_start && layers_.walks;
}
SnapshotEncodeCache::SnapshotEncodeCache(SnapshotEncodeCache&&) noexcept = default;
SnapshotEncodeCache& SnapshotEncodeCache::operator=(SnapshotEncodeCache&&) noexcept = default;
SnapshotEncodeCache::~SnapshotEncodeCache() = default;

struct SnapshotEncoder::Scratch {
  explicit Scratch(const QuantizationSpec& spec) : widths(spec) {}
  layout::FieldWidths widths;
  EncodeBuffers buffers;
  DeltaTable deltas;                      ///< when encoding without a cache
  std::vector<QuantizedEntity> baseline;  ///< a world baseline made whole, when needed
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

void SnapshotEncoder::encode(std::uint32_t tick, std::span<const QuantizedEntity> world,
                             std::array<float, 3> viewer_m, std::size_t budget_bytes,
                             wire::Snapshot& out, SnapshotEncodeCache& cache) {
  encode_with(tick, world, viewer_m, budget_bytes, out, &cache);
}

void SnapshotEncoder::encode_with(std::uint32_t tick, std::span<const QuantizedEntity> world,
                                  std::array<float, 3> viewer_m, std::size_t budget_bytes,
                                  wire::Snapshot& out, SnapshotEncodeCache* cache) {
  assert(!has_sent_ || tick > last_tick_);
  assert(std::is_sorted(world.begin(), world.end(),
                        [](const auto& a, const auto& b) { return a.id < b.id; }));

  // The baseline: the newest acknowledged snapshot, while the ring still holds it; either a
  // view of the client's own or a world but for exceptions.
  const Sent& acked = slot(acked_tick_);
  const bool has_baseline = has_ack_ && acked.valid && acked.tick == acked_tick_;
  const bool baseline_is_world = has_baseline && acked.world_token != 0;
  const WorldBaseline world_baseline =
      baseline_is_world ? WorldBaseline{*acked.world, acked.held, acked.held_states, acked.absent}
                        : WorldBaseline{};
  std::span<const QuantizedEntity> baseline = has_baseline && !baseline_is_world
                                                  ? std::span<const QuantizedEntity>(acked.view)
                                                  : std::span<const QuantizedEntity>();
  const std::size_t baseline_size = baseline_is_world
                                        ? world_baseline.world.size() - world_baseline.absent.size()
                                        : baseline.size();
  const std::uint32_t baseline_age = has_baseline ? tick - acked_tick_ : 0;

  const std::size_t header = header_bytes(tick, baseline_age, budget_bytes);
  const std::size_t stream_budget_bytes = budget_bytes > header ? budget_bytes - header : 0;
  // Counts, orders and padding come before any entity.
  const std::size_t fixed_bits = 3 + (2 + layout::kDeltaOrderCount) * layout::kOrderBits + 8;

  const std::size_t select_budget_bits =
      stream_budget_bytes * 8 > fixed_bits ? stream_budget_bytes * 8 - fixed_bits : 0;

  // Another client of this tick with this baseline, for whom everything fitted: when it all
  // fits this budget too, select takes every candidate whatever their priorities, write writes
  // that client's stream, and nothing is left to carry. Baselines are matched by token, so
  // only one that was a whole world (or none) can share a stream.
  SnapshotEncodeCache::Streams* shared = cache ? cache->streams_.get() : nullptr;
  const SnapshotCacheLayers layers = cache ? cache->layers_
                                           : SnapshotCacheLayers{.streams = false,
                                                                 .deltas = false,
                                                                 .world_baselines = false,
                                                                 .walks = false,
                                                                 .whole_world_start = false};
  const SharedStream* reused = nullptr;
  const layout::Prediction prediction = layout::make_prediction(baseline_age, spec_);
  const std::uint64_t baseline_token = has_baseline ? acked.world_token : 0;
  const bool shareable =
      layers.streams &&
      (!has_baseline || (baseline_token != 0 && acked.held.empty() && acked.absent.empty()));
  if (shared) shared->begin(tick, world, scratch_->widths, spec_, layers);
  if (shareable) {
    const SharedStream* found = shared->find(baseline_token, baseline_age, prediction);
    if (found && found->candidate_bits <= select_budget_bits &&
        found->stream.size() <= stream_budget_bytes) {
      reused = found;
    }
  }

  out.Clear();
  out.set_tick(tick);
  out.set_baseline_age(baseline_age);
  std::size_t pending = 0, sent = 0;
  // The view: this world but for next_held_ (at next_held_states_) and next_absent_.
  bool world_but_exceptions = true;
  next_held_.clear();
  next_held_states_.clear();
  next_absent_.clear();
  if (reused) {
    ++cache->hits_;
    priority_.clear();
    pending = sent = reused->pending;
    assign_bytes(*out.mutable_entities(), reused->stream);
  } else {
    DeltaTable& deltas = layers.deltas ? shared->deltas : scratch_->deltas;
    if (!layers.deltas) deltas.reset(world, spec_);
    // A baseline that is a world the cache saw (but for a few entities) follows the walk
    // against that world, recorded by the first client of the tick to need it. Without walks
    // it is the world made whole.
    const bool whole_world = acked.held.empty() && acked.absent.empty();
    const bool follow_walk =
        baseline_is_world && layers.walks && (layers.whole_world_start || whole_world);
    if (baseline_is_world && !follow_walk) {
      hold(world_baseline, scratch_->baseline);
      baseline = scratch_->baseline;
    }
    EncodePass pass(spec_, options_, baseline, baseline_size, baseline_age, world, scratch_->widths,
                    scratch_->buffers, deltas);
    if (follow_walk) {
      SharedWalk* walk = shared->find_walk(baseline_token, prediction);
      if (!walk) {
        walk = &shared->claim_walk(baseline_token, prediction);
        pass.record_walk(world_baseline.world, *walk);
      }
      ++cache->walks_followed_;
      if (!layers.whole_world_start) {
        pass.find_pending(priority_, viewer_m, *walk, world_baseline.world);
        pass.estimate_costs();
      } else if (walk->whole_world_start.valid) {
        pass.take_start(walk->whole_world_start, world_baseline, priority_, viewer_m);
      } else if (whole_world) {
        pass.find_pending(priority_, viewer_m, *walk, world_baseline.world);
        pass.estimate_costs();
        pass.keep_start(*walk, walk->whole_world_start);
      } else {
        // The start is a follower holding the whole world, worked out first.
        {
          EncodePass start(spec_, options_, {}, world_baseline.world.size(), baseline_age, world,
                           scratch_->widths, scratch_->buffers, deltas);
          start.find_pending({}, viewer_m, *walk, world_baseline.world);
          start.estimate_costs();
          start.keep_start(*walk, walk->whole_world_start);
        }
        pass.take_start(walk->whole_world_start, world_baseline, priority_, viewer_m);
      }
    } else {
      pass.find_pending(priority_, viewer_m);
      pass.estimate_costs();
    }
    pass.select(select_budget_bits);
    bool fits = false;
    while (!fits) fits = pass.write(stream_, stream_budget_bytes);  // each miss leaves some out
    if (pass.removal_deferred()) {
      if (baseline.size() != baseline_size) {  // followed a walk: make the baseline whole
        hold(world_baseline, scratch_->baseline);
        pass.use_baseline(scratch_->baseline);
      }
      pass.merge_view(next_view_);
      world_but_exceptions = false;
    } else {
      pass.list_deferred(next_held_, next_held_states_, next_absent_);
    }
    pending = pass.pending();
    sent = pass.carry_priorities(priority_);
    assign_bytes(*out.mutable_entities(), stream_.bytes());
    if (shared) ++cache->misses_;
    // Everything sent means the first write fitted (a miss leaves something out).
    if (shareable && sent == pending) {
      SharedStream& entry = shared->claim();
      entry.baseline_token = baseline_token;
      entry.baseline_age = baseline_age;
      entry.prediction = prediction;
      entry.candidate_bits = pass.candidate_bits();
      entry.pending = static_cast<std::uint32_t>(pending);
      entry.stream.assign(stream_.bytes().begin(), stream_.bytes().end());
    }
  }

  // Remember what the client will hold; this may overwrite the baseline's slot, used no more.
  // Without a cache the view is the client's own, and so is one with exceptions without world
  // baselines.
  const bool held_as_world =
      shared && (layers.world_baselines || (next_held_.empty() && next_absent_.empty()));
  if (world_but_exceptions && !held_as_world) {
    hold({world, next_held_, next_held_states_, next_absent_}, next_view_);
    world_but_exceptions = false;
  }
  Sent& entry = slot(tick);
  entry.valid = true;
  entry.tick = tick;
  entry.world_token = world_but_exceptions ? shared->world_token : 0;
  entry.world = world_but_exceptions ? shared->world_now : nullptr;
  if (world_but_exceptions) {
    entry.view.clear();
  } else {
    entry.view.swap(next_view_);
  }
  entry.held.swap(next_held_);
  entry.held_states.swap(next_held_states_);
  entry.absent.swap(next_absent_);
  has_sent_ = true;
  last_tick_ = tick;

  report_.has_baseline = has_baseline;
  report_.baseline_tick = has_baseline ? acked_tick_ : 0;
  report_.entities = static_cast<std::uint32_t>(world.size());
  report_.pending = static_cast<std::uint32_t>(pending);
  report_.sent = static_cast<std::uint32_t>(sent);
  report_.deferred = static_cast<std::uint32_t>(pending - sent);
  report_.bytes = out.ByteSizeLong();
}

}  // namespace ricochet::proto
