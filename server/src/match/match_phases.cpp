/// The phases of a match's step and snapshot that move things and tell the clients (match.h):
/// apply inputs, movement, physics step, record history, build snapshots, send. The rules,
/// combat and recording phases have their own files.

#include <cassert>
#include <utility>

#include "ricochet/proto/entity_flags.h"
#include "ricochet/server/match.h"

namespace ricochet::server {

namespace {

/// ServerPayload fields around the snapshot: three uint32 (tag + up to 5 bytes each), the
/// snapshot's tag and length (1 + 2 bytes) and the PlayerStatus (at most 2 + 45 bytes: five
/// small ints, three ammo counts, two ticks), so the whole payload stays within the budget.
constexpr std::size_t kPayloadOverheadBytes = 3 * 6 + 3 + 47;

std::array<float, 3> to_array(const physics::Vec3& v) {
  return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
}

}  // namespace

void Match::apply_inputs() {
  step_inputs_.clear();
  for (Player& player : players_) {
    if (!player.connected) continue;  // away: the neutral input disconnect() left
    bool repeated = false;
    player.applied = player.inputs.next(repeated);
    ++(repeated ? counters_.inputs_repeated : counters_.inputs_applied);
    step_inputs_.push_back(RecordedInput{player.entity_id, player.applied,
                                         static_cast<std::uint32_t>(player.latency_us)});
  }
}

void Match::move_players() {
  const float dt_s = static_cast<float>(clock_.step_s());
  for (Player& player : players_) {
    if (!player.alive) continue;  // no body until the respawn
    const physics::BodyState state = world_.body_state(player.body).value();
    player.grounded = is_grounded(world_, player.body, state.radius, config_.movement);
    const physics::Vec3 velocity = move_velocity(config_.movement, player.applied,
                                                 state.linear_velocity, player.grounded, dt_s);
    [[maybe_unused]] const physics::Status set = world_.set_linear_velocity(player.body, velocity);
    assert(set.ok());  // validated inputs give finite velocities
  }
}

void Match::step_physics() {
  [[maybe_unused]] const physics::Status stepped =
      world_.step(static_cast<physics::Real>(clock_.step_s()));
  assert(stepped.ok());  // the step is 1/128..1/10 s
  ++tick_;
}

void Match::record_history() {
  // Read every live body in one call: the players', then the grenades'.
  body_ids_.clear();
  for (const Player& player : players_) {
    if (player.alive) body_ids_.push_back(player.body);
  }
  for (const Projectile& shot : projectiles_) {
    if (!shot.grenade.is_null()) body_ids_.push_back(shot.grenade);
  }
  positions_.resize(body_ids_.size());
  velocities_.resize(body_ids_.size());
  physics::BodyReadout readout;
  readout.positions = positions_;
  readout.linear_velocities = velocities_;
  [[maybe_unused]] const physics::Status read = world_.read_bodies(body_ids_, readout);
  assert(read.ok());  // every listed body is live
  std::size_t next = 0;
  for (Player& player : players_) {
    if (!player.alive) continue;
    player.position_m = positions_[next];
    player.velocity_mps = velocities_[next];
    ++next;
  }
  for (Projectile& shot : projectiles_) {
    if (!shot.grenade.is_null()) {
      shot.position_m = positions_[next];
      shot.velocity_mps = velocities_[next];
      ++next;
    } else if (const auto state = world_.projectile_state(shot.rocket); state.ok()) {
      shot.position_m = state.value().position;
      shot.velocity_mps = state.value().velocity;
    }
  }

  lag_samples_.clear();
  const physics::Real radius = player_body_def(physics::Vec3::Zero()).radius;
  for (const Player& player : players_) {
    lag_samples_.push_back(LagSample{player.entity_id, player.body, player.position_m,
                                     static_cast<float>(radius), player.life, player.alive});
  }
  lag_.record(tick_, lag_samples_);

  // Players and projectiles, merged by id (both lists are sorted by it).
  HistoryEntry& entry = history_[tick_ % history_.size()];
  entry.tick = tick_;
  entry.states.clear();
  std::size_t p = 0, q = 0;
  while (p < players_.size() || q < projectiles_.size()) {
    proto::EntityState state;
    if (q == projectiles_.size() ||
        (p < players_.size() && players_[p].entity_id < projectiles_[q].entity_id)) {
      const Player& player = players_[p++];
      state.id = player.entity_id;
      state.position_m = to_array(player.position_m);
      state.velocity_mps = player.alive ? to_array(player.velocity_mps) : std::array<float, 3>{};
      state.flags = static_cast<std::uint8_t>(
          (player.grounded && player.alive ? proto::kEntityGrounded : 0) |
          (player.connected ? 0 : proto::kEntityDisconnected) |
          (player.alive ? 0 : proto::kEntityDead) |
          (player.alive && tick_ < player.protected_until ? proto::kEntityProtected : 0));
    } else {
      const Projectile& shot = projectiles_[q++];
      state.id = shot.entity_id;
      state.position_m = to_array(shot.position_m);
      state.velocity_mps = to_array(shot.velocity_mps);
      state.flags =
          proto::kind_flags(shot.weapon == WeaponKind::GrenadeLauncher ? proto::EntityKind::Grenade
                                                                       : proto::EntityKind::Rocket);
    }
    state.orientation_xyzw = {0, 0, 0, 1};  // players never spin; projectiles are round
    entry.states.push_back(state);
  }
}

void Match::build_snapshots() {
  const std::span<const proto::EntityState> states = entity_states();
  quantized_.resize(states.size());
  for (std::size_t k = 0; k < states.size(); ++k) {
    quantized_[k] = proto::quantize(states[k], config_.quantization);
  }
  payload_count_ = 0;
  for (Player& player : players_) {
    if (!player.connected) continue;
    if (payload_count_ == payloads_.size()) payloads_.emplace_back();
    AddressedPayload& addressed = payloads_[payload_count_++];
    addressed.account = player.account;
    wire::ServerPayload& payload = addressed.payload;
    if (player.snapshot_ack != 0)
      player.snapshots->acknowledge(std::exchange(player.snapshot_ack, 0));
    player.snapshots->encode(tick_, quantized_, to_array(player.position_m),
                             config_.snapshot_budget_bytes - kPayloadOverheadBytes,
                             *payload.mutable_snapshot(), snapshot_cache_);
    payload.set_last_input_sequence(player.inputs.last_applied_sequence());
    payload.set_server_tick(tick_);
    payload.set_your_entity_id(player.entity_id);
    wire::PlayerStatus& status = *payload.mutable_status();
    status.set_health(player.vitals.health);
    status.set_armor(player.vitals.armor);
    status.set_weapon(to_wire(player.weapon));
    status.clear_ammo();
    for (const int rounds : player.ammo) status.add_ammo(rounds);
    status.set_alive(player.alive);
    status.set_respawn_tick(player.alive ? 0 : player.respawn_tick);
    status.set_protected_until_tick(player.protected_until);
    status.set_team(static_cast<wire::Team>(player.team));
  }
}

void Match::send() {
  // Events first: a PlayerJoined arrives no later than the first snapshot showing the entity
  // on a link without loss.
  counters_.events_sent += pending_events_.size();
  for (Outgoing& event : pending_events_) outbox_.push_back(std::move(event));
  pending_events_.clear();
  for (std::size_t k = 0; k < payload_count_; ++k) {
    const AddressedPayload& addressed = payloads_[k];
    Outgoing out;
    out.account = addressed.account;
    out.reliable = false;
    out.bytes.resize(addressed.payload.ByteSizeLong());
    addressed.payload.SerializeToArray(out.bytes.data(), static_cast<int>(out.bytes.size()));
    counters_.snapshot_bytes += out.bytes.size();
    ++counters_.snapshots_sent;
    outbox_.push_back(std::move(out));
  }
  payload_count_ = 0;
}

}  // namespace ricochet::server
