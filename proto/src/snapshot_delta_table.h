#pragma once
/// The deltas one tick's encodes share (DeltaTable) and the order tallies they choose their
/// field orders from (FieldTallies): private to the snapshot encoder.

#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "ricochet/proto/quantize.h"
#include "snapshot_layout.h"
#include "snapshot_orders.h"

namespace ricochet::proto {

namespace layout = snapshot_layout;

/// QuantizedEntity's ==, one field after another, positions (the likeliest to differ) first;
/// the defaulted one calls memcmp per array.
inline bool same_state(const QuantizedEntity& a, const QuantizedEntity& b) {
  if (a.position[0] != b.position[0] || a.position[1] != b.position[1] ||
      a.position[2] != b.position[2]) {
    return false;
  }
  if (a.velocity[0] != b.velocity[0] || a.velocity[1] != b.velocity[1] ||
      a.velocity[2] != b.velocity[2]) {
    return false;
  }
  return a.id == b.id && a.orientation_largest == b.orientation_largest &&
         a.orientation[0] == b.orientation[0] && a.orientation[1] == b.orientation[1] &&
         a.orientation[2] == b.orientation[2] && a.flags == b.flags;
}

/// The order tallies of changed entities' fields, from which an encode chooses its orders, one
/// delta added or taken back at a time.
struct FieldTallies {
  std::array<layout::OrderTally, 3> position, velocity;
  layout::OrderTally orientation;

  void add(const layout::Delta& delta) { visit(delta, &layout::OrderTally::add); }
  void remove(const layout::Delta& delta) { visit(delta, &layout::OrderTally::remove); }
  void choose(layout::DeltaOrders& orders) const {
    for (int a = 0; a < 3; ++a) {
      orders.position[a] = position[a].best();
      orders.velocity[a] = velocity[a].best();
    }
    orders.orientation = orientation.best();
  }

 private:
  void visit(const layout::Delta& delta, void (layout::OrderTally::*op)(std::uint64_t)) {
    for (int a = 0; a < 3; ++a) {
      if (delta.mask & layout::kPositionChanged) (position[a].*op)(delta.position[a]);
      if (delta.mask & layout::kVelocityChanged) (velocity[a].*op)(delta.velocity[a]);
      if ((delta.mask & layout::kOrientationChanged) && delta.same_largest) {
        (orientation.*op)(delta.orientation[a]);
      }
    }
  }
};

/// The deltas of one tick's changed entities, per world index, each against the baseline state
/// and age it was worked out for, with its fields written for the orders an encode last chose
/// (layout::DeltaBody). Every encoder has one of its own; a SnapshotEncodeCache holds one that
/// its encoders share, so that clients holding the same baseline state of an entity at the same
/// age share its delta, change and bits instead of working them out again.
///
/// The table also tallies the fields of every delta it holds, per prediction (baseline age):
/// a client's tally is its group's minus the deltas it does not use, which are few when the
/// clients hold much the same baselines, instead of a sum over all its changed entities.
class DeltaTable {
 public:
  struct Way {
    std::uint64_t generation = 0;
    std::int32_t group = -1;    ///< whose tallies hold this delta; -1: none
    std::uint32_t listed = 0;   ///< bit g: in group g's list this generation
    std::uint64_t used_by = 0;  ///< the last pass (begin_pass) that took this delta
    /// Which claim put the delta here (unique in the table): a way remembered with its stamp
    /// still holds that delta while the stamps agree.
    std::uint64_t stamp = 0;
    layout::Prediction prediction;
    QuantizedEntity baseline;
    layout::Delta delta;
    double change_m = 0;
    /// The fields written for the kBodies sets of orders last asked for (clients of one tick
    /// mostly choose one or two), each with its layout::field_orders_key.
    struct Body {
      bool valid = false;
      std::uint64_t orders = 0;
      layout::DeltaBody bits;
    };
    static constexpr std::uint8_t kBodies = 4;
    std::array<Body, kBodies> bodies;
    std::uint8_t next_body = 0;  ///< the one replaced next
  };

  /// The fields of `way`'s delta written with `orders` (whose key is `orders_key`), written now
  /// if no body has them.
  const layout::DeltaBody& body(Way& way, const layout::DeltaOrders& orders,
                                std::uint64_t orders_key, const layout::FieldWidths& widths) {
    if (const layout::DeltaBody* written = find_body(way, orders_key)) return *written;
    Way::Body& body = way.bodies[way.next_body];
    way.next_body = static_cast<std::uint8_t>((way.next_body + 1) % Way::kBodies);
    replaced_ += body.valid;
    layout::write_delta_body(body.bits, way.delta, orders, widths);
    body.orders = orders_key;
    body.valid = true;
    return body.bits;
  }
  /// The fields of `way`'s delta written with the orders of `orders_key`, or null.
  static const layout::DeltaBody* find_body(const Way& way, std::uint64_t orders_key) {
    for (const Way::Body& body : way.bodies) {
      if (body.valid && body.orders == orders_key) return &body.bits;
    }
    return nullptr;
  }
  /// How many deltas and bodies of this generation were replaced by others: while it stays the
  /// same, every Way and DeltaBody handed out this generation still holds what it held.
  std::uint64_t replaced() const { return replaced_; }

  /// Forgets every delta (nothing is cleared: each remembers the generation it was made in)
  /// and takes the positions of `world`, whose entities the deltas will be of.
  void reset(std::span<const QuantizedEntity> world, const QuantizationSpec& spec) {
    ++generation_;
    if (ways_.size() < world.size() * kWays) ways_.resize(world.size() * kWays);
    for (int a = 0; a < 3; ++a) {
      std::vector<float>& axis = positions_m_[a];
      axis.resize(world.size());
      for (std::size_t i = 0; i < world.size(); ++i) {
        axis[i] =
            static_cast<float>(spec.bounds.min_m[a] +
                               static_cast<double>(world[i].position[a]) * spec.position_step_m);
      }
    }
  }
  /// The weight 1 / (1 + d / scale_m) of every world entity at its distance d from `viewer_m`
  /// (finite), in one pass over the positions that the compiler vectorises.
  void distance_weights(std::array<float, 3> viewer_m, float scale_m,
                        std::vector<float>& weights) const {
    const std::size_t count = positions_m_[0].size();
    weights.resize(count);
    const float* x = positions_m_[0].data();
    const float* y = positions_m_[1].data();
    const float* z = positions_m_[2].data();
    float* out = weights.data();
    for (std::size_t i = 0; i < count; ++i) {
      const float dx = x[i] - viewer_m[0], dy = y[i] - viewer_m[1], dz = z[i] - viewer_m[2];
      out[i] = 1.0f / (1.0f + std::sqrt(dx * dx + dy * dy + dz * dz) / scale_m);
    }
  }
  /// The world's entity `world_index` written as a new entity, once per generation.
  const layout::AbsoluteBody& absolute(std::size_t world_index, const QuantizedEntity& entity,
                                       const layout::FieldWidths& widths) {
    if (absolutes_.size() <= world_index) absolutes_.resize(positions_m_[0].size());
    Absolute& absolute = absolutes_[world_index];
    if (absolute.generation != generation_) {
      absolute.generation = generation_;
      layout::write_absolute_body(absolute.body, entity, widths);
    }
    return absolute.body;
  }

  static constexpr std::size_t kWays = 2;
  std::uint64_t generation() const { return generation_; }
  /// A number for one encode's pass, to mark the deltas it takes (Way::used_by).
  std::uint64_t begin_pass() { return ++passes_; }

  /// The group of `prediction` this generation, or -1 when it has none.
  std::int32_t group_of(const layout::Prediction& prediction) const {
    for (std::size_t g = 0; g < kGroups; ++g) {
      if (groups_[g].generation == generation_ && groups_[g].prediction == prediction) {
        return static_cast<std::int32_t>(g);
      }
    }
    return -1;
  }
  /// The tallies of the deltas of the group's prediction that `pass` took: the group's tally
  /// of all of them, less those it did not take.
  void tallies_of_pass(std::int32_t group, std::uint64_t pass, FieldTallies& out) const {
    const Group& g = groups_[static_cast<std::size_t>(group)];
    out = g.tallies;
    for (const Way* way : g.ways) {
      // A way listed once may since hold another prediction's delta.
      if (way->generation == generation_ && way->group == group && way->used_by != pass) {
        out.remove(way->delta);
      }
    }
  }

  Way* find(std::size_t world_index, const QuantizedEntity& baseline,
            const layout::Prediction& prediction) {
    for (std::size_t w = 0; w < kWays; ++w) {
      Way& way = ways_[world_index * kWays + w];
      if (way.generation == generation_ && way.prediction == prediction &&
          same_state(way.baseline, baseline)) {
        return &way;
      }
    }
    return nullptr;
  }

  /// A way for a delta not found: a free one, else the last (the first keeps the commonest),
  /// holding this baseline's delta.
  Way& claim(std::size_t world_index, const QuantizedEntity& baseline, const QuantizedEntity& now,
             const layout::FieldWidths& widths, const layout::Prediction& prediction,
             double change_m) {
    Way* ways = &ways_[world_index * kWays];
    Way* way = &ways[kWays - 1];
    for (std::size_t w = 0; w + 1 < kWays; ++w) {
      if (ways[w].generation != generation_) {
        way = &ways[w];
        break;
      }
    }
    if (way->generation == generation_) {
      ++replaced_;
      if (way->group >= 0) groups_[static_cast<std::size_t>(way->group)].tallies.remove(way->delta);
    }
    way->stamp = ++claims_;
    way->prediction = prediction;
    way->baseline = baseline;
    way->delta = layout::make_delta(baseline, now, widths, prediction);
    way->change_m = change_m;
    for (Way::Body& body : way->bodies) body.valid = false;
    way->next_body = 0;
    if (way->generation != generation_) way->listed = 0;
    way->generation = generation_;
    way->group = claim_group(prediction);
    if (way->group >= 0) {
      Group& group = groups_[static_cast<std::size_t>(way->group)];
      group.tallies.add(way->delta);
      const std::uint32_t bit = 1u << way->group;
      if (!(way->listed & bit)) {
        way->listed |= bit;
        group.ways.push_back(way);
      }
    }
    return *way;
  }

 private:
  /// Baseline ages tallied per generation; deltas of further ages are tallied by their encodes.
  static constexpr std::size_t kGroups = 4;
  struct Group {
    std::uint64_t generation = 0;
    layout::Prediction prediction;
    FieldTallies tallies;
    std::vector<Way*> ways;  ///< every way given to the group this generation, once
  };

  /// The group of `prediction`, opened if there is room (a group, once full, stays so for the
  /// generation, so a prediction either has every one of its deltas tallied or none).
  std::int32_t claim_group(const layout::Prediction& prediction) {
    if (const std::int32_t found = group_of(prediction); found >= 0) return found;
    for (std::size_t g = 0; g < kGroups; ++g) {
      if (groups_[g].generation != generation_) {
        groups_[g].generation = generation_;
        groups_[g].prediction = prediction;
        groups_[g].tallies = FieldTallies{};
        groups_[g].ways.clear();
        return static_cast<std::int32_t>(g);
      }
    }
    return -1;
  }

  std::uint64_t generation_ = 0;
  std::uint64_t passes_ = 0;
  std::uint64_t claims_ = 0;
  std::uint64_t replaced_ = 0;
  std::vector<Way> ways_;
  /// The world's positions dequantised, m, per axis.
  std::array<std::vector<float>, 3> positions_m_;
  struct Absolute {
    std::uint64_t generation = 0;
    layout::AbsoluteBody body;
  };
  std::vector<Absolute> absolutes_;
  std::array<Group, kGroups> groups_;
};

}  // namespace ricochet::proto
