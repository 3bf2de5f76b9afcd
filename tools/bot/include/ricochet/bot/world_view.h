#pragma once
/// What a bot knows of the match: the entities of the newest decoded snapshot (dequantised, with
/// the game's flags decoded), its own entity, the players' teams, and what it learned from the
/// reliable events: where players spawn and where the pickups are. The protocol does not carry
/// pickup positions; a Pickup event names the entity that took it, which stood within 1 m of it,
/// so the view learns a pickup's place from the taker's position in the newest snapshot.
///
/// The view shows the newest snapshot as is; a RenderedView (rendered_view.h) copies it and
/// show()s the interpolated others and the predicted own player instead.

#include <array>
#include <boost/unordered/unordered_flat_map.hpp>
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "ricochet/proto/entity_flags.h"
#include "ricochet/proto/quantize.h"
#include "ricochet/wire/game.pb.h"

namespace ricochet::bot {

using Vec3 = std::array<float, 3>;

/// |a - b|, m, in double.
inline double distance_m(const Vec3& a, const Vec3& b) {
  double d2 = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const double d = double(a[axis]) - double(b[axis]);
    d2 += d * d;
  }
  return std::sqrt(d2);
}

struct SeenEntity {
  std::uint32_t id = 0;
  Vec3 position_m{};
  Vec3 velocity_mps{};
  std::uint8_t flags = 0;  ///< proto::EntityFlag bits and the kind

  /// Nothing for a kind the protocol does not assign.
  std::optional<proto::EntityKind> kind() const { return proto::entity_kind(flags); }
  bool is_living_player() const {
    return kind() == proto::EntityKind::Player &&
           (flags & (proto::kEntityDead | proto::kEntityDisconnected)) == 0;
  }
};

struct KnownPickup {
  wire::PickupKind kind = wire::PICKUP_KIND_UNSPECIFIED;
  bool up = true;
  std::optional<Vec3> position_m;  ///< learned from a taker; unknown until someone takes it
};

class WorldView {
 public:
  explicit WorldView(const proto::QuantizationSpec& spec) : spec_(spec) {}

  /// A decoded snapshot of `tick` (entities sorted by id) and the payload's own entity.
  void apply_snapshot(std::uint32_t tick, std::uint32_t own_entity_id,
                      std::span<const proto::QuantizedEntity> entities);
  /// Replaces the entities (sorted by id) and the tick shown: what the bot renders instead of
  /// the newest snapshot.
  void show(std::uint32_t tick, std::vector<SeenEntity> entities) {
    tick_ = tick;
    entities_ = std::move(entities);
  }
  /// A reliable game event (already parsed; its values are checked here before use).
  void apply_event(const wire::GameEvent& event);

  std::uint32_t tick() const { return tick_; }
  std::uint32_t own_id() const { return own_id_; }
  const SeenEntity* own() const;
  const SeenEntity* find(std::uint32_t id) const;
  const std::vector<SeenEntity>& entities() const { return entities_; }
  /// The nearest living player that is not this bot nor a team-mate; nullptr when none.
  const SeenEntity* nearest_enemy() const;
  /// Where players were seen to spawn (walkable places), m, at most kMaxSpawnPoints.
  const std::vector<Vec3>& spawn_points() const { return spawn_points_; }
  const boost::unordered_flat_map<std::uint32_t, KnownPickup>& pickups() const { return pickups_; }
  wire::MatchPhase phase() const { return phase_; }
  const proto::SnapshotBounds& bounds() const { return spec_.bounds; }

  static constexpr std::size_t kMaxSpawnPoints = 64;
  static constexpr std::size_t kMaxPickups = 256;

 private:
  proto::QuantizationSpec spec_;
  std::uint32_t tick_ = 0;
  std::uint32_t own_id_ = 0;
  std::vector<SeenEntity> entities_;
  // Open addressing: nearest_enemy looks teams up for every player of every snapshot.
  boost::unordered_flat_map<std::uint32_t, wire::Team> teams_;  ///< by entity, from Spawned
  std::vector<Vec3> spawn_points_;
  boost::unordered_flat_map<std::uint32_t, KnownPickup> pickups_;  ///< by the map's pickup index
  wire::MatchPhase phase_ = wire::MATCH_PHASE_UNSPECIFIED;
};

}  // namespace ricochet::bot
