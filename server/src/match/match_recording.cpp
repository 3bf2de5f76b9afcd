/// A match's recording (match_recorder.h, recording.h): the membership changes between steps,
/// every applied input per step, and the match hash every hash_interval_ticks steps.

#include <cstring>

#include "match_recorder.h"

namespace ricochet::server {

namespace {

/// 64-bit FNV-1a, fed field by field.
class Fnv1a {
 public:
  template <typename T>
  void add(const T& value) {
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    for (const unsigned char byte : bytes) {
      hash_ ^= byte;
      hash_ *= 0x100000001b3ull;
    }
  }
  void add_vec(const physics::Vec3& v) {
    for (int axis = 0; axis < 3; ++axis) add(v[axis]);
  }
  std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ull;
};

}  // namespace

void record_step(std::uint32_t tick, std::optional<std::uint64_t> hash, Recorder& recorder,
                 MatchCounters& counters) {
  RecordingWriter* writer = recorder.writer.get();
  if (!writer) return;
  if (writer->full()) {
    counters.recording_truncated = true;
    recorder.pending_events.clear();
    return;
  }
  writer->begin_tick(tick);
  for (const RecordedEvent& event : recorder.pending_events) writer->add_event(event);
  recorder.pending_events.clear();
  for (const RecordedInput& input : recorder.step_inputs) writer->add_input(input);
  if (hash) writer->add_hash(tick, *hash);
  writer->end_tick();
  counters.recording_bytes = writer->bytes();
}

std::uint64_t match_hash(const physics::World& world, std::uint32_t tick, const RulesState& rules,
                         const Roster& roster, const Combat& combat) {
  Fnv1a hash;
  hash.add(world.state_hash());
  hash.add(tick);
  hash.add(static_cast<std::uint8_t>(rules.phase));
  hash.add(rules.phase_ends_tick);
  hash.add(rules.team_scores);
  hash.add(rules.rng);  // the generator's whole state
  for (const Player& player : roster.players) {
    hash.add(player.entity_id);
    hash.add(player.alive);
    hash.add(player.life);
    hash.add(player.vitals.health);
    hash.add(player.vitals.armor);
    hash.add(player.ammo);
    hash.add(player.weapon);
    hash.add(player.respawn_tick);
    hash.add(player.protected_until);
    hash.add(player.next_fire_tick);
    hash.add(player.aim_yaw_rad);
    hash.add(player.aim_pitch_rad);
    hash.add(player.score.kills);
    hash.add(player.score.deaths);
    hash.add(player.score.score);
    hash.add(player.score.shots);
    hash.add(player.score.hits);
    hash.add(player.score.damage_dealt);
    hash.add(player.score.damage_taken);
    hash.add_vec(player.position_m);
  }
  for (const Projectile& shot : combat.projectiles) {
    hash.add(shot.entity_id);
    hash.add(shot.expires_tick);
    hash.add_vec(shot.position_m);
  }
  for (const PickupState& pickup : rules.pickups) {
    hash.add(pickup.available);
    hash.add(pickup.respawn_tick);
  }
  return hash.value();
}

}  // namespace ricochet::server
