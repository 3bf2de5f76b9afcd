#pragma once
/// The plain per-client snapshot encode (snapshot_encoder.cpp) as steps the encode cache's
/// paths (snapshot_encode_cache.cpp) also take: the candidates, the pass and the encoder's
/// working state. Private to the snapshot encoder.

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "ricochet/proto/bit_stream.h"
#include "ricochet/proto/snapshot_codec.h"
#include "snapshot_delta_table.h"
#include "snapshot_layout.h"

namespace ricochet::proto {

/// Removals go before everything: they are cheap and a gone entity must not linger.
inline constexpr float kRemovalPriority = 1e9f;
/// A new entity counts as this much change, m.
inline constexpr float kNewEntityChange_m = 1.0f;
/// How much a changed flag byte or orientation counts, m.
inline constexpr float kFlagsChange_m = 1.0f;
inline constexpr float kOrientationChange_m = 0.05f;
/// Velocity change counts as the distance it covers in this long, s.
inline constexpr float kVelocityHorizon_s = 0.1f;
/// A changed entity counts at least this much, m, however small its change.
inline constexpr float kMinimumChange_m = 0.01f;

inline std::size_t varint_bytes(std::uint64_t value) {
  std::size_t bytes = 1;
  while (value >= 0x80) {
    value >>= 7;
    ++bytes;
  }
  return bytes;
}

/// Bytes of a wire::Snapshot around an entity stream of at most budget_bytes.
inline std::size_t header_bytes(std::uint32_t tick, std::uint32_t baseline_age,
                                std::size_t budget_bytes) {
  std::size_t bytes = 1 + varint_bytes(tick) + 1 + varint_bytes(budget_bytes);
  if (baseline_age != 0) bytes += 1 + varint_bytes(baseline_age);
  return bytes;
}

/// Copies `bytes` into a protobuf bytes field, keeping its capacity (the iterator form of
/// assign copies one char at a time).
inline void assign_bytes(std::string& field, const std::vector<std::uint8_t>& bytes) {
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
inline void hold(const WorldBaseline& baseline, std::vector<QuantizedEntity>& view) {
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

/// The buffers of one encode (SnapshotEncoder::Scratch holds them between encodes).
struct EncodeBuffers {
  std::vector<Candidate> candidates;
  std::vector<std::pair<float, std::uint32_t>> drop_heap;  ///< drop_lowest's
  std::vector<float> weights;                              ///< weigh_priorities': per world entity
  FieldTallies tallies;                                    ///< estimate_costs'
  std::vector<std::uint64_t> removed_gaps, added_gaps, changed_gaps;  ///< write's
  std::vector<std::uint32_t> added;
  std::vector<const Candidate*> changed;
};

/// One encode: the baseline and the world, what differs, what goes in, the stream and the view
/// the client will hold. Each step is one method; SnapshotEncoder::encode calls them in order.
/// The cache's passes (snapshot_encode_cache.cpp) add the steps that follow a walk.
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
  inline void find_pending(std::span<const std::pair<std::uint32_t, float>> carried,
                           std::array<float, 3> viewer_m);
  /// Chooses the field orders over all candidates and estimates each candidate's bits.
  void estimate_costs();
  /// Selects everything that fits budget_bits by priority, highest first.
  inline void select(std::size_t budget_bits);
  /// Writes the selected candidates; false if the stream exceeds stream_budget_bytes, after
  /// leaving out about as many of the lowest priorities as the excess needs (call again).
  inline bool write(BitWriter& stream, std::size_t stream_budget_bytes);
  /// Whether a removal was left out (practically never: removals go first). Otherwise the
  /// client holds the world after decoding the stream but for the deferred entities.
  inline bool removal_deferred() const;
  /// The deferred entities by world index: `held` (changed: the client keeps `held_states`,
  /// their baseline states) and `absent` (new: not held at all).
  inline void list_deferred(std::vector<std::uint32_t>& held,
                            std::vector<QuantizedEntity>& held_states,
                            std::vector<std::uint32_t>& absent) const;
  /// The entity set the client holds after decoding the stream, merged from the baseline
  /// (which must be whole: use_baseline) and the candidates.
  inline void merge_view(std::vector<QuantizedEntity>& view) const;
  /// Whether the pass holds the client's whole baseline (not when it follows a walk).
  bool has_whole_baseline() const { return baseline_.size() == baseline_size_; }
  /// The client's whole baseline, for merge_view after following a walk.
  void use_baseline(std::span<const QuantizedEntity> baseline) { baseline_ = baseline; }
  /// Deferred entities' priorities, sorted by id; returns how many candidates were sent.
  inline std::size_t carry_priorities(std::vector<std::pair<std::uint32_t, float>>& carried) const;
  std::size_t pending() const { return candidates_.size(); }
  /// estimate_costs' bits of every candidate, summed.
  std::size_t candidate_bits() const {
    std::size_t bits = 0;
    for (const Candidate& c : candidates_) bits += static_cast<std::size_t>(c.bits);
    return bits;
  }

 protected:  // the cache's passes (snapshot_encode_cache.cpp) follow walks with these
  /// Unselects the selected candidate of lowest priority (of equal ones, the last) and
  /// returns it; the first call orders the selected candidates, which must not be empty.
  inline Candidate& drop_lowest();
  /// Sets a candidate's bits for the orders_ (whose key is orders_key) and a gap estimate.
  void cost(Candidate& c, std::uint64_t orders_key, int gap_estimate);
  /// What the client carried for the entity `id`; ids must increase from call to call.
  float carried_priority(std::uint32_t id);
  /// Adds each candidate's change at its distance to what it carried: only an encode that
  /// leaves something out needs its priorities.
  inline void weigh_priorities();
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

// The steps the cache's passes take too, inline in both files.

inline double EncodePass::change_m(const QuantizedEntity& then, const QuantizedEntity& now) const {
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

inline DeltaTable::Way& EncodePass::delta_of(std::size_t i, const QuantizedEntity& then) {
  if (DeltaTable::Way* way = deltas_.find(i, then, prediction_)) return *way;
  return deltas_.claim(i, then, world_[i], widths_, prediction_, change_m(then, world_[i]));
}

inline void EncodePass::add_world_candidate(Candidate::Kind kind, std::size_t j, std::size_t i,
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

inline float EncodePass::carried_priority(std::uint32_t id) {
  std::size_t& p = carried_next_;
  while (p < carried_.size() && carried_[p].first < id) ++p;
  return p < carried_.size() && carried_[p].first == id ? carried_[p].second : 0;
}

inline void EncodePass::look_from(std::span<const std::pair<std::uint32_t, float>> carried,
                                  std::array<float, 3> viewer_m) {
  carried_ = carried;
  // A viewer nowhere (NaN or infinite) sees everything as near, so priorities stay ordered.
  viewer_nowhere_ =
      !std::isfinite(viewer_m[0]) || !std::isfinite(viewer_m[1]) || !std::isfinite(viewer_m[2]);
  viewer_m_ = viewer_m;
  candidates_.reserve(world_.size() + baseline_size_);
}

inline void EncodePass::add_removed(std::size_t j) {
  candidates_.push_back({.kind = Candidate::Kind::Removed,
                         .baseline_index = static_cast<std::uint32_t>(j),
                         .priority = kRemovalPriority});
}

inline void EncodePass::compare_kept(std::size_t i, std::size_t j, const QuantizedEntity& then) {
  if (same_state(world_[i], then)) return;
  DeltaTable::Way& way = delta_of(i, then);
  way.used_by = pass_;
  add_world_candidate(Candidate::Kind::Changed, j, i, &way, way.change_m, &then);
}

inline void EncodePass::cost(Candidate& c, std::uint64_t orders_key, int gap_estimate) {
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

/// The acknowledged snapshot an encode deltas against.
struct SnapshotEncoder::Baseline {
  bool exists = false;
  std::uint32_t age = 0;  ///< tick - its tick; 0 without one
  /// The client's own entities; empty when `is_world`.
  std::span<const QuantizedEntity> view;
  /// A world a SnapshotEncodeCache saw (named by `world_token`) but for exceptions.
  bool is_world = false;
  WorldBaseline world;
  std::uint64_t world_token = 0;
  std::size_t size = 0;  ///< entities the client holds

  /// A world with no exceptions: the client holds all of it.
  bool whole_world() const { return is_world && world.held.empty() && world.absent.empty(); }
};

/// An encode's budget for the entity stream.
struct SnapshotEncoder::Budget {
  std::size_t stream_bytes = 0;  ///< the budget less the Snapshot's other fields
  std::size_t select_bits = 0;   ///< less the counts, orders and padding too
};

/// What an encode sent and what the client holds once it decodes it.
struct SnapshotEncoder::Outcome {
  std::size_t pending = 0, sent = 0;
  std::size_t candidate_bits = 0;  ///< when everything was sent: the estimates, summed
  /// The view is this tick's world but for next_held_ (at next_held_states_) and next_absent_;
  /// otherwise it is next_view_.
  bool world_but_exceptions = true;
  /// When the client holds the cache's copy of the world (then world_but_exceptions), that
  /// copy and its token; else null and 0.
  std::shared_ptr<const std::vector<QuantizedEntity>> shared_world;
  std::uint64_t world_token = 0;
};

/// The spec's field widths and encode's working buffers, kept from call to call so that
/// encoding allocates nothing once they have grown to the world's size.
struct SnapshotEncoder::Scratch {
  explicit Scratch(const QuantizationSpec& spec) : widths(spec) {}
  layout::FieldWidths widths;
  EncodeBuffers buffers;
  DeltaTable deltas;                      ///< the encoder's own (the cache has a shared one)
  std::vector<QuantizedEntity> baseline;  ///< a world baseline made whole, when needed
};

}  // namespace ricochet::proto
