/// A match's recording and its playback (match.h, recording.h): the membership changes between
/// steps, every applied input per step, and the match hash every hash_interval_ticks steps.

#include <cassert>
#include <cstring>

#include "ricochet/server/match.h"

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

void Match::record_event(const RecordedEvent& event) {
  if (recording_) pending_record_events_.push_back(event);
}

void Match::record_step() {
  if (!recording_) return;
  if (recording_->full()) {
    counters_.recording_truncated = true;
    pending_record_events_.clear();
    return;
  }
  recording_->begin_tick(tick_);
  for (const RecordedEvent& event : pending_record_events_) recording_->add_event(event);
  pending_record_events_.clear();
  for (const RecordedInput& input : step_inputs_) recording_->add_input(input);
  if (tick_ % static_cast<std::uint32_t>(config_.hash_interval_ticks) == 0) {
    recording_->add_hash(tick_, state_hash());
  }
  recording_->end_tick();
  counters_.recording_bytes = recording_->bytes();
}

std::vector<std::uint8_t> Match::take_recording() {
  if (!recording_) return {};
  std::vector<std::uint8_t> bytes = recording_->finish();
  recording_.reset();
  return bytes;
}

void Match::apply(const RecordedEvent& event) {
  switch (event.kind) {
    case RecordedEventKind::Connect:
      connect(event.account, event.name);
      break;
    case RecordedEventKind::Disconnect:
      disconnect(event.account, 0);
      break;
    case RecordedEventKind::Leave:
      leave(event.account);
      break;
    case RecordedEventKind::TimedOut:
      for (std::size_t k = 0; k < players_.size(); ++k) {
        if (players_[k].account == event.account) {
          time_out(k);
          break;
        }
      }
      break;
    case RecordedEventKind::End:
      end(static_cast<wire::MatchEndReason>(event.end_reason));
      break;
  }
  outbox_.clear();  // nobody listens to a replay
  outbox_read_ = 0;
  pending_events_.clear();
}

void Match::step_recorded(std::span<const RecordedInput> inputs) {
  if (ended()) return;
  step_inputs_.assign(inputs.begin(), inputs.end());
  for (Player& player : players_) player.applied = PlayerInput{};
  for (const RecordedInput& input : inputs) {
    if (Player* player = find_entity(input.entity_id)) {
      player->applied = input.input;
      player->latency_us = input.latency_us;
    }
  }
  simulate_step();
  ++counters_.steps;
  pending_events_.clear();
}

std::uint64_t Match::state_hash() const {
  Fnv1a hash;
  hash.add(world_.state_hash());
  hash.add(tick_);
  hash.add(static_cast<std::uint8_t>(phase_));
  hash.add(phase_ends_tick_);
  hash.add(team_scores_);
  hash.add(rng_);  // the generator's whole state
  for (const Player& player : players_) {
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
  for (const Projectile& shot : projectiles_) {
    hash.add(shot.entity_id);
    hash.add(shot.expires_tick);
    hash.add_vec(shot.position_m);
  }
  for (const PickupState& pickup : pickups_) {
    hash.add(pickup.available);
    hash.add(pickup.respawn_tick);
  }
  return hash.value();
}

}  // namespace ricochet::server
