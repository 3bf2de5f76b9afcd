/// SnapshotEncodeCache: the work the encoders of one match share within a tick, in layers on top
/// of the plain per-client encoder (snapshot_encoder.cpp). Every layer writes the bytes the
/// plain encoder writes (tests/proto/snapshot_cache_test.cpp, tests/fuzz/snapshot_cache_fuzz.cpp)
/// and can be switched off (SnapshotCacheLayers, match-bench --cache-off).
///
/// What each layer costs to keep right and what it saves, in instructions (callgrind) of one
/// match in match-bench, every layer on against that layer off (a layer off takes those that
/// need it with it); figures and commands in tools/bench/results/snapshot_cache_layers.jsonl.
/// "% of a core" scales the saving by the snapshots' share of a core at 1300 bots (16-player
/// matches), first with every client acknowledging alike (100 ms), then spread over 1..5 ticks
/// as the bots' round trips are; a negative saving means the layer costs more than it saves.
///
// clang-format off
/// layer              invalidated by                             saves, % of a core   saves, % of
///                                                               at 1300 bots         the 64-player
///                                                               (alike / spread)     tick (alike)
/// streams            a new tick (world, widths); the baseline's      23.7 / -0.1         93.2
///                    token, age and prediction; the budget's fit
/// deltas             a new tick (generation); per entity its         -0.3 / +0.1         41.9
///                    baseline state and prediction, a way's stamp;
///                    a body's orders key
/// world_baselines    a new tick (world token); a client's held        0.0 /  0.0          3.8
///                    and absent entities
/// walks              the baseline's token and prediction; the        -0.3 / -0.6          7.0
///                    stamps of the deltas it points to
/// whole_world_start  the delta table's replacements, the stamps,     -0.3 / -0.4          5.3
///                    the orders key
// clang-format on
///
/// Why every layer stays: streams saves far more than 2 % of a core; the other four save less
/// than 2 % of a core in 16-player matches, but the 64-player tick needs them (all four off
/// cost it 42.9 % more instructions), and its p99 must stay <= 1 ms (0.78..0.90 ms in
/// tools/bench/results/match.jsonl). world_baselines, the one that saves no instructions even
/// there, is what keeps a tick's world once instead of a copy per client: match-bench's max RSS
/// went 50.8 -> 21.1 MB with it (commit d22c538, tools/bench/README.md). At a capacity step with
/// each layer off (tools/bench/CAPACITY.md, 2026-12-05) the whole cache saved 22.6 points of the
/// server's core and streams at least 3.1; the other layers' effects were below what the VM's
/// drifting speed lets one step resolve, which is why the decision rests on instruction counts.

#include <algorithm>
#include <atomic>
#include <optional>

#include "ricochet/proto/snapshot_codec.h"
#include "snapshot_delta_table.h"
#include "snapshot_encode_pass.h"
#include "snapshot_layout.h"

namespace ricochet::proto {

namespace {

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

/// An encode pass that can follow a walk: record it, follow it, or start from the whole-world
/// start a follower kept.
class WalkingPass : public EncodePass {
 public:
  /// For a baseline that is a world but for exceptions, of baseline_size entities.
  WalkingPass(const QuantizationSpec& spec, const SnapshotEncoderOptions& options,
              std::size_t baseline_size, std::uint32_t baseline_age,
              std::span<const QuantizedEntity> world, const layout::FieldWidths& widths,
              EncodeBuffers& buffers, DeltaTable& deltas, std::vector<StartEdit>& edits)
      : EncodePass(spec, options, {}, baseline_size, baseline_age, world, widths, buffers, deltas),
        edits_(edits) {}

  /// Records the walk of the world against `earlier` (a world the cache saw) into `walk`, with
  /// the delta of every changed entity.
  void record_walk(std::span<const QuantizedEntity> earlier, SharedWalk& walk);
  /// find_pending for a baseline that is the whole world `walk` was recorded against,
  /// `earlier`: follows the walk.
  void find_pending(std::span<const std::pair<std::uint32_t, float>> carried,
                    std::array<float, 3> viewer_m, const SharedWalk& walk,
                    std::span<const QuantizedEntity> earlier);
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

 private:
  std::vector<StartEdit>& edits_;
};

void WalkingPass::record_walk(std::span<const QuantizedEntity> earlier, SharedWalk& walk) {
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

void WalkingPass::find_pending(std::span<const std::pair<std::uint32_t, float>> carried,
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

void WalkingPass::keep_start(const SharedWalk& walk, SharedWalk::WholeWorldStart& start) const {
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

void WalkingPass::take_start(const SharedWalk::WholeWorldStart& start,
                             const WorldBaseline& baseline,
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
  std::vector<StartEdit>& edits = edits_;
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
  std::vector<StartEdit> edits;            ///< take_start's, for the encode under way
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

  /// This tick's stream against the baseline of `baseline_token` at this age and prediction,
  /// when everything it sent fits `budget` too; else null.
  const SharedStream* find(std::uint64_t baseline_token, std::uint32_t baseline_age,
                           const layout::Prediction& prediction,
                           const SnapshotEncoder::Budget& budget) const {
    for (std::size_t k = 0; k < used; ++k) {
      const SharedStream& entry = entries[k];
      if (entry.baseline_token == baseline_token && entry.baseline_age == baseline_age &&
          entry.prediction == prediction) {
        const bool fits = entry.candidate_bits <= budget.select_bits &&
                          entry.stream.size() <= budget.stream_bytes;
        return fits ? &entry : nullptr;
      }
    }
    return nullptr;
  }
  /// Keeps a stream that sent everything, for the clients after it with that baseline and age.
  void keep(std::uint64_t baseline_token, std::uint32_t baseline_age,
            const layout::Prediction& prediction, const SnapshotEncoder::Outcome& outcome,
            const std::vector<std::uint8_t>& stream) {
    SharedStream& entry = claim_slot(entries, used, next_replaced);
    entry.baseline_token = baseline_token;
    entry.baseline_age = baseline_age;
    entry.prediction = prediction;
    entry.candidate_bits = outcome.candidate_bits;
    entry.pending = static_cast<std::uint32_t>(outcome.pending);
    entry.stream.assign(stream.begin(), stream.end());
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

  /// The next unused of `slots` this tick, else the one used longest ago.
  template <typename Slot>
  static Slot& claim_slot(std::vector<Slot>& slots, std::size_t& used, std::size_t& next_replaced) {
    if (used < slots.size()) return slots[used++];
    Slot& slot = slots[next_replaced];
    next_replaced = (next_replaced + 1) % slots.size();
    return slot;
  }
};

bool switch_off_cache_layer(std::string_view name, SnapshotCacheLayers& layers) {
  const bool all = name == "all";
  bool known = all;
  const auto off = [&](std::string_view layer, bool& on) {
    if (all || name == layer) on = false;
    known |= name == layer;
  };
  off("streams", layers.streams);
  off("deltas", layers.deltas);
  off("world_baselines", layers.world_baselines);
  off("walks", layers.walks);
  off("whole_world_start", layers.whole_world_start);
  return known;
}

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

void SnapshotEncoder::encode(std::uint32_t tick, std::span<const QuantizedEntity> world,
                             std::array<float, 3> viewer_m, std::size_t budget_bytes,
                             wire::Snapshot& out, SnapshotEncodeCache& cache) {
  encode_with(tick, world, viewer_m, budget_bytes, out, &cache);
}

SnapshotEncoder::Outcome SnapshotEncoder::encode_cached(const Baseline& baseline,
                                                        std::uint32_t tick,
                                                        std::span<const QuantizedEntity> world,
                                                        std::array<float, 3> viewer_m,
                                                        const Budget& budget, wire::Snapshot& out,
                                                        SnapshotEncodeCache& cache) {
  SnapshotEncodeCache::Streams& shared = *cache.streams_;
  const SnapshotCacheLayers& layers = cache.layers_;
  shared.begin(tick, world, scratch_->widths, spec_, layers);
  // Another client of this tick with this baseline, for whom everything fitted: when it all
  // fits this budget too, select takes every candidate whatever their priorities, write writes
  // that client's stream, and nothing is left to carry. Baselines are matched by token, so
  // only one that was a whole world (or none) can share a stream.
  const layout::Prediction prediction = layout::make_prediction(baseline.age, spec_);
  const bool shareable = layers.streams && (!baseline.exists || baseline.whole_world());
  const SharedStream* reused =
      shareable ? shared.find(baseline.world_token, baseline.age, prediction, budget) : nullptr;
  Outcome outcome;
  if (reused) {
    ++cache.hits_;
    priority_.clear();
    outcome.pending = outcome.sent = reused->pending;
    assign_bytes(*out.mutable_entities(), reused->stream);
  } else {
    ++cache.misses_;
    if (baseline.is_world && layers.walks && (layers.whole_world_start || baseline.whole_world())) {
      outcome = follow_walk(baseline, world, viewer_m, budget, out, cache);
    } else {
      DeltaTable& deltas = layers.deltas ? shared.deltas : scratch_->deltas;
      if (!layers.deltas) deltas.reset(world, spec_);
      outcome = encode_against(baseline, deltas, world, viewer_m, budget, out);
    }
    if (shareable && outcome.sent == outcome.pending) {
      shared.keep(baseline.world_token, baseline.age, prediction, outcome, stream_.bytes());
    }
  }
  // A client holding the world but for exceptions holds the tick's one copy of it.
  if (outcome.world_but_exceptions &&
      (layers.world_baselines || (next_held_.empty() && next_absent_.empty()))) {
    outcome.shared_world = shared.world_now;
    outcome.world_token = shared.world_token;
  }
  return outcome;
}

SnapshotEncoder::Outcome SnapshotEncoder::follow_walk(const Baseline& baseline,
                                                      std::span<const QuantizedEntity> world,
                                                      std::array<float, 3> viewer_m,
                                                      const Budget& budget, wire::Snapshot& out,
                                                      SnapshotEncodeCache& cache) {
  // The walk against the baseline's world, recorded by the first client of the tick to need it.
  SnapshotEncodeCache::Streams& shared = *cache.streams_;
  const layout::Prediction prediction = layout::make_prediction(baseline.age, spec_);
  WalkingPass pass(spec_, options_, baseline.size, baseline.age, world, scratch_->widths,
                   scratch_->buffers, shared.deltas, shared.edits);
  SharedWalk* walk = shared.find_walk(baseline.world_token, prediction);
  if (!walk) {
    walk = &shared.claim_walk(baseline.world_token, prediction);
    pass.record_walk(baseline.world.world, *walk);
  }
  ++cache.walks_followed_;
  if (!cache.layers_.whole_world_start) {
    pass.find_pending(priority_, viewer_m, *walk, baseline.world.world);
    pass.estimate_costs();
  } else if (walk->whole_world_start.valid) {
    pass.take_start(walk->whole_world_start, baseline.world, priority_, viewer_m);
  } else if (baseline.whole_world()) {
    pass.find_pending(priority_, viewer_m, *walk, baseline.world.world);
    pass.estimate_costs();
    pass.keep_start(*walk, walk->whole_world_start);
  } else {
    // The start is a follower holding the whole world, worked out first.
    {
      WalkingPass start(spec_, options_, baseline.world.world.size(), baseline.age, world,
                        scratch_->widths, scratch_->buffers, shared.deltas, shared.edits);
      start.find_pending({}, viewer_m, *walk, baseline.world.world);
      start.estimate_costs();
      start.keep_start(*walk, walk->whole_world_start);
    }
    pass.take_start(walk->whole_world_start, baseline.world, priority_, viewer_m);
  }
  return finish(pass, baseline, budget, out);
}

}  // namespace ricochet::proto
