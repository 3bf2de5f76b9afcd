/// The phases of a match's tick (match.h): apply inputs, movement, physics step, record
/// history, build snapshots, send.

#include <cassert>

#include "ricochet/server/match.h"

namespace ricochet::server {

namespace {

/// ServerPayload fields around the snapshot: three uint32 (tag + up to 5 bytes each) and the
/// snapshot's tag and length (1 + 2 bytes), so the whole payload stays within the budget.
constexpr std::size_t kPayloadOverheadBytes = 3 * 6 + 3;

std::array<float, 3> to_array(const physics::Vec3& v) {
  return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
}

}  // namespace

void Match::apply_inputs() {
  for (Player& player : players_) {
    if (!player.connected) continue;  // away: the neutral input disconnect() left
    bool repeated = false;
    player.applied = player.inputs.next(repeated);
    ++(repeated ? counters_.inputs_repeated : counters_.inputs_applied);
  }
}

void Match::move_players() {
  const float dt_s = static_cast<float>(clock_.step_s());
  for (Player& player : players_) {
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
  const std::size_t count = players_.size();
  body_ids_.resize(count);
  positions_.resize(count);
  velocities_.resize(count);
  for (std::size_t k = 0; k < count; ++k) body_ids_[k] = players_[k].body;
  physics::BodyReadout readout;
  readout.positions = positions_;
  readout.linear_velocities = velocities_;
  [[maybe_unused]] const physics::Status read = world_.read_bodies(body_ids_, readout);
  assert(read.ok());  // every player's body is live

  HistoryEntry& entry = history_[tick_ % history_.size()];
  entry.tick = tick_;
  entry.states.resize(count);
  for (std::size_t k = 0; k < count; ++k) {
    const Player& player = players_[k];
    proto::EntityState& state = entry.states[k];
    state.id = player.entity_id;  // players_ is sorted by entity id, so are the states
    state.position_m = to_array(positions_[k]);
    state.velocity_mps = to_array(velocities_[k]);
    state.orientation_xyzw = {0, 0, 0, 1};  // players never spin (arena_players)
    state.flags = static_cast<std::uint8_t>((player.grounded ? kEntityGrounded : 0) |
                                            (player.connected ? 0 : kEntityDisconnected));
  }
}

void Match::build_snapshots() {
  const std::span<const proto::EntityState> states = entity_states();
  quantized_.resize(states.size());
  for (std::size_t k = 0; k < states.size(); ++k) {
    quantized_[k] = proto::quantize(states[k], config_.quantization);
  }
  payload_count_ = 0;
  for (std::size_t k = 0; k < players_.size(); ++k) {
    Player& player = players_[k];
    if (!player.connected) continue;
    if (payload_count_ == payloads_.size()) payloads_.emplace_back();
    AddressedPayload& addressed = payloads_[payload_count_++];
    addressed.account = player.account;
    wire::ServerPayload& payload = addressed.payload;
    player.snapshots->encode(tick_, quantized_, states[k].position_m,
                             config_.snapshot_budget_bytes - kPayloadOverheadBytes,
                             *payload.mutable_snapshot());
    payload.set_last_input_sequence(player.inputs.last_applied_sequence());
    payload.set_server_tick(tick_);
    payload.set_your_entity_id(player.entity_id);
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
