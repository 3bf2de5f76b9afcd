#include "ricochet/bot/world_view.h"

#include <cmath>
#include <limits>

namespace ricochet::bot {

void WorldView::apply_snapshot(std::uint32_t tick, std::uint32_t own_entity_id,
                               std::span<const proto::QuantizedEntity> entities) {
  tick_ = tick;
  own_id_ = own_entity_id;
  entities_.clear();
  entities_.reserve(entities.size());
  for (const proto::QuantizedEntity& quantized : entities) {
    SeenEntity& seen = entities_.emplace_back();
    seen.id = quantized.id;
    seen.flags = quantized.flags;
    proto::dequantize_motion(quantized, spec_, seen.position_m, seen.velocity_mps);
  }
}

const SeenEntity* WorldView::find(std::uint32_t id) const {
  // entities_ is sorted by id (the decoder's order).
  std::size_t low = 0;
  std::size_t high = entities_.size();
  while (low < high) {
    const std::size_t mid = (low + high) / 2;
    if (entities_[mid].id < id) {
      low = mid + 1;
    } else {
      high = mid;
    }
  }
  return low < entities_.size() && entities_[low].id == id ? &entities_[low] : nullptr;
}

const SeenEntity* WorldView::own() const {
  return own_id_ ? find(own_id_) : nullptr;
}

const SeenEntity* WorldView::nearest_enemy() const {
  const SeenEntity* self = own();
  if (!self) return nullptr;
  const auto own_team = teams_.find(own_id_);
  const bool teamed = own_team != teams_.end() && own_team->second != wire::TEAM_NONE;
  const auto team_mate = [&](std::uint32_t id) {
    const auto team = teams_.find(id);
    return team != teams_.end() && team->second == own_team->second;
  };
  const SeenEntity* best = nullptr;
  float best_d2 = std::numeric_limits<float>::max();
  for (const SeenEntity& other : entities_) {
    if (other.id == own_id_ || !other.is_living_player()) continue;
    float d2 = 0;
    for (int a = 0; a < 3; ++a) {
      const float d = other.position_m[a] - self->position_m[a];
      d2 += d * d;
    }
    // The team is looked up only for a player nearer than the best so far.
    if (d2 < best_d2 && !(teamed && team_mate(other.id))) {
      best_d2 = d2;
      best = &other;
    }
  }
  return best;
}

void WorldView::apply_event(const wire::GameEvent& event) {
  switch (event.event_case()) {
    case wire::GameEvent::kSpawned: {
      const wire::Spawned& spawned = event.spawned();
      teams_[spawned.entity_id()] = spawned.team();
      if (spawned.position_size() != 3) break;
      Vec3 position{spawned.position(0), spawned.position(1), spawned.position(2)};
      bool finite = true;
      for (const float v : position) finite = finite && std::isfinite(v);
      if (!finite) break;
      for (const Vec3& known : spawn_points_) {
        float d2 = 0;
        for (int a = 0; a < 3; ++a) d2 += (known[a] - position[a]) * (known[a] - position[a]);
        if (d2 < 1.0f) return;
      }
      if (spawn_points_.size() < kMaxSpawnPoints) spawn_points_.push_back(position);
      break;
    }
    case wire::GameEvent::kPickup: {
      const wire::Pickup& pickup = event.pickup();
      if (pickups_.size() >= kMaxPickups && !pickups_.count(pickup.pickup_index())) break;
      KnownPickup& known = pickups_[pickup.pickup_index()];
      known.kind = pickup.kind();
      known.up = pickup.entity_id() == 0;
      if (!known.up) {
        if (const SeenEntity* taker = find(pickup.entity_id()))
          known.position_m = taker->position_m;
      }
      break;
    }
    case wire::GameEvent::kMatchState:
      phase_ = event.match_state().phase();
      if (phase_ == wire::MATCH_PHASE_RUNNING) {
        // Entering running resets the pickups: every one is up again.
        for (auto& [index, known] : pickups_) known.up = true;
      }
      break;
    case wire::GameEvent::kPlayerLeft:
      teams_.erase(event.player_left().entity_id());
      break;
    default:
      break;
  }
}

}  // namespace ricochet::bot
