/// A match's players, untrusted payloads, chat and the tick's table of contents (match.h). The
/// phases themselves are in match_phases.cpp.

#include "ricochet/server/match.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "ricochet/physics/scene_profile.h"

namespace ricochet::server {

const char* name(JoinRefusal reason) {
  switch (reason) {
    case JoinRefusal::MatchFull:
      return "match_full";
    case JoinRefusal::InvalidName:
      return "invalid_name";
    case JoinRefusal::MatchEnded:
      return "match_ended";
  }
  return "unknown";
}

const char* name(ChatDrop reason) {
  switch (reason) {
    case ChatDrop::NotInMatch:
      return "not_in_match";
    case ChatDrop::Empty:
      return "empty";
    case ChatDrop::TooLong:
      return "too_long";
    case ChatDrop::InvalidText:
      return "invalid_text";
  }
  return "unknown";
}

std::variant<Match, std::string> Match::create(const MatchConfig& config, const Map& map,
                                               proto::TimeUs now, ProfileClock profile_clock) {
  if (std::string error = config.validate(); !error.empty()) return error;
  if (map.spawns.empty()) return "map " + map.name + " has no spawn point";
  proto::QuantizationSpec spec = config.quantization;
  for (int axis = 0; axis < 3; ++axis) {
    spec.bounds.min_m[static_cast<std::size_t>(axis)] = static_cast<float>(map.bounds_min_m[axis]);
    spec.bounds.max_m[static_cast<std::size_t>(axis)] = static_cast<float>(map.bounds_max_m[axis]);
  }
  // The codec predicts positions from velocities over one step of this match's tick.
  spec.tick_s = 1.0f / static_cast<float>(config.tick.rate_hz);
  if (std::string error = spec.validate(); !error.empty()) {
    return "match quantization (with the bounds of map " + map.name + "): " + error;
  }
  physics::Result<physics::World> world = physics::World::create(combat_world_def());
  if (!world.ok()) return "physics world: " + world.error().message;
  if (const physics::Status added = add_map_to_world(map, world.value()); !added.ok()) {
    return "map " + map.name + ": " + added.error().message;
  }
  MatchConfig resolved = config;
  resolved.quantization = spec;
  return Match(resolved, std::move(world).value(), map, now, std::move(profile_clock));
}

Match::Match(const MatchConfig& config, physics::World world, const Map& map, proto::TimeUs now,
             ProfileClock profile_clock)
    : config_(config),
      map_name_(map.name),
      map_(map),
      world_(std::move(world)),
      clock_(config.tick, now),
      profile_clock_(std::move(profile_clock)),
      rng_(config.rules.seed),
      lag_(config.lag, config.tick.rate_hz),
      history_(static_cast<std::size_t>(config.history_ticks)),
      snapshot_cache_(config.snapshot_cache_layers) {
  for (const MapPickup& spot : map.pickups) pickups_.push_back(PickupState{spot, true, 0});
  snapshot_interval_ticks_ = std::max(
      1, static_cast<int>(std::lround(double(config.tick.rate_hz) / config.snapshot_rate_hz)));
  ticks_since_snapshot_ = snapshot_interval_ticks_;  // the first step sends one
  if (config.record) {
    RecordingHeader header;
    header.server_version = "ricochet-match 1";
    for (const MapFile& file : map.files) header.map_files.push_back({file.path, file.text});
    header.config = encode_match_config(config_);
    header.seed = config.rules.seed;
    header.hash_interval_ticks = static_cast<std::uint32_t>(config.hash_interval_ticks);
    header.tick_rate_hz = static_cast<std::uint32_t>(config.tick.rate_hz);
    recording_ = std::make_unique<RecordingWriter>(std::move(header), config.max_recording_bytes);
  }
}

Match::Match(Match&&) noexcept = default;
Match& Match::operator=(Match&&) noexcept = default;
Match::~Match() = default;

// --- players ---

Match::Player* Match::find(std::uint64_t account) {
  for (Player& player : players_) {
    if (player.account == account) return &player;
  }
  return nullptr;
}

const Match::Player* Match::find(std::uint64_t account) const {
  return const_cast<Match*>(this)->find(account);
}

std::variant<Joined, JoinRefusal> Match::connect(std::uint64_t account, std::string_view name) {
  const auto refuse = [this](JoinRefusal reason) {
    ++counters_.join_refusals[static_cast<std::size_t>(reason)];
    return reason;
  };
  if (ended()) return refuse(JoinRefusal::MatchEnded);
  if (name.empty() || name.size() > kMaxPlayerNameBytes || !is_printable_utf8(name)) {
    return refuse(JoinRefusal::InvalidName);
  }
  wire::GameEvent joined;
  if (Player* player = find(account)) {
    // Back within the grace, or a new connection replacing one still open: same entity, a new
    // client (sequence from 1, no snapshot baseline).
    player->connected = true;
    player->name = std::string(name);
    player->inputs.reset();
    player->applied = PlayerInput{};
    player->snapshots = std::make_unique<proto::SnapshotEncoder>(config_.quantization);
    player->snapshot_ack = 0;
    drop_pending_events(account);  // meant for the old connection
    ++counters_.players_reconnected;
    record_event(RecordedEvent{RecordedEventKind::Connect, account, std::string(name), 0});
    for (const Player& other : players_) {
      if (other.account != account) queue_present(account, other);
    }
    queue_arrival(account);
    joined.mutable_player_joined()->set_entity_id(player->entity_id);
    joined.mutable_player_joined()->set_name(player->name);
    joined.mutable_player_joined()->set_reconnected(true);
    broadcast(joined);
    return Joined{player->entity_id, true};
  }
  if (player_count() >= config_.max_players) return refuse(JoinRefusal::MatchFull);

  record_event(RecordedEvent{RecordedEventKind::Connect, account, std::string(name), 0});
  Player player;
  player.account = account;
  player.name = std::string(name);
  player.entity_id = next_entity_id_++;
  player.inputs = InputBuffer(config_.input);
  player.snapshots = std::make_unique<proto::SnapshotEncoder>(config_.quantization);
  player.team = balanced_team();
  // A player coming back after leaving keeps what it scored.
  const auto before =
      std::find_if(departed_.begin(), departed_.end(),
                   [account](const PlayerScore& s) { return s.account == account; });
  if (before != departed_.end()) {
    player.score = *before;
    departed_.erase(before);
  }
  player.score.account = account;
  player.score.name = player.name;
  player.score.entity_id = player.entity_id;
  player.score.team = player.team;
  // Everyone already here, to the newcomer; then the newcomer to everyone (itself included).
  for (const Player& other : players_) queue_present(account, other);
  queue_arrival(account);
  const Joined result{player.entity_id, false};
  joined.mutable_player_joined()->set_entity_id(player.entity_id);
  joined.mutable_player_joined()->set_name(player.name);
  players_.push_back(std::move(player));
  broadcast(joined);
  spawn(players_.back());
  ++counters_.players_joined;
  return result;
}

void Match::disconnect(std::uint64_t account, proto::TimeUs now) {
  Player* player = find(account);
  if (!player || !player->connected) return;
  record_event(RecordedEvent{RecordedEventKind::Disconnect, account, {}, 0});
  player->connected = false;
  player->disconnected_at = now;
  player->inputs.reset();  // the entity stands still while away
  player->applied = PlayerInput{};
  player->snapshots.reset();
  player->snapshot_ack = 0;
  drop_pending_events(account);
}

bool Match::leave(std::uint64_t account) {
  for (std::size_t k = 0; k < players_.size(); ++k) {
    if (players_[k].account == account) {
      record_event(RecordedEvent{RecordedEventKind::Leave, account, {}, 0});
      remove_player(k, wire::LEAVE_REASON_LEFT);
      ++counters_.players_left;
      return true;
    }
  }
  return false;
}

void Match::remove_player(std::size_t index, wire::LeaveReason reason) {
  const Player& player = players_[index];
  if (!player.body.is_null()) {
    [[maybe_unused]] const physics::Status destroyed = world_.destroy_body(player.body);
    assert(destroyed.ok());
  }
  if (player.score.ticks_played > 0 || player.score.shots > 0 || player.score.deaths > 0) {
    departed_.push_back(player.score);
  }
  wire::GameEvent left;
  left.mutable_player_left()->set_entity_id(player.entity_id);
  left.mutable_player_left()->set_name(player.name);
  left.mutable_player_left()->set_reason(reason);
  const std::uint64_t account = player.account;
  players_.erase(players_.begin() + static_cast<std::ptrdiff_t>(index));
  drop_pending_events(account);
  broadcast(left);
}

void Match::expire_disconnected(proto::TimeUs now) {
  for (std::size_t k = players_.size(); k-- > 0;) {
    const Player& player = players_[k];
    if (!player.connected && now - player.disconnected_at >= config_.reconnect_grace_us) {
      time_out(k);
    }
  }
}

void Match::time_out(std::size_t index) {
  record_event(RecordedEvent{RecordedEventKind::TimedOut, players_[index].account, {}, 0});
  remove_player(index, wire::LEAVE_REASON_TIMED_OUT);
  ++counters_.players_timed_out;
}

void Match::receive(std::uint64_t account, std::span<const std::uint8_t> payload) {
  const auto drop = [this](InputDrop reason) {
    ++counters_.input_drops[static_cast<std::size_t>(reason)];
  };
  Player* player = find(account);
  if (!player || !player->connected) return drop(InputDrop::UnknownPlayer);
  wire::ClientPayload& message = incoming_;
  if (payload.size() > proto::kMaxClientPayloadBytes ||
      !message.ParseFromArray(payload.data(), static_cast<int>(payload.size()))) {
    return drop(InputDrop::MalformedPayload);
  }
  if (static_cast<std::size_t>(message.inputs_size()) > proto::kMaxInputsPerPayload) {
    return drop(InputDrop::TooManyInputs);
  }
  ++counters_.payloads_received;
  // Input rate: a client sends one input per tick; a window of one second may bring more
  // (input_rate_limit: clock drift, bursts after a stall). Beyond that the inputs are refused: a
  // sped-up client gains nothing and is counted.
  const std::uint32_t window = static_cast<std::uint32_t>(config_.tick.rate_hz);
  if (tick_ - player->input_window_start >= window) {
    player->input_window_start = tick_;
    player->inputs_in_window = 0;
  }
  const auto allowed = static_cast<std::uint32_t>(input_rate_limit(config_.tick.rate_hz));
  for (const wire::Input& in : message.inputs()) {
    PlayerInput input;
    InputDrop reason{};
    if (!validate_input(in, input, reason)) {
      drop(reason);
      continue;
    }
    if (!player->inputs.is_new(input.sequence)) {
      drop(InputDrop::Stale);  // the redundancy: not counted against the rate
      continue;
    }
    if (player->inputs_in_window >= allowed) {
      drop(InputDrop::Skipped);
      note_violation(*player, Violation::InputRate);
      continue;
    }
    ++player->inputs_in_window;
    player->inputs.offer(input, counters_.input_drops);
  }
  // Only the newest acknowledgement counts (SnapshotEncoder::acknowledge ignores older ones).
  player->snapshot_ack = std::max(player->snapshot_ack, message.ack_snapshot_tick());
}

void Match::set_latency(std::uint64_t account, proto::TimeUs one_way_us) {
  if (Player* player = find(account)) {
    player->latency_us = std::clamp<proto::TimeUs>(one_way_us, 0, proto::kMicrosPerSecond);
  }
}

std::optional<ChatDrop> Match::chat(std::uint64_t account, std::string_view text) {
  std::optional<ChatDrop> refusal;
  const Player* player = find(account);
  if (!player || !player->connected)
    refusal = ChatDrop::NotInMatch;
  else if (text.empty())
    refusal = ChatDrop::Empty;
  else if (text.size() > kMaxChatBytes)
    refusal = ChatDrop::TooLong;
  else if (!is_printable_utf8(text))
    refusal = ChatDrop::InvalidText;
  if (refusal) {
    ++counters_.chat_drops[static_cast<std::size_t>(*refusal)];
    return refusal;
  }
  wire::GameEvent event;
  wire::ChatMessage& line = *event.mutable_chat();
  line.set_entity_id(player->entity_id);
  line.set_name(player->name);
  line.set_text(std::string(text));
  broadcast(event);
  ++counters_.chat_messages;
  return std::nullopt;
}

void Match::end(wire::MatchEndReason reason) {
  if (ended()) return;
  finish(reason);
  payload_count_ = 0;  // no snapshot goes with it
  send();
}

void Match::queue_event(std::uint64_t account, const wire::GameEvent& event) {
  Outgoing out;
  out.account = account;
  out.reliable = true;
  out.bytes.resize(event.ByteSizeLong());
  event.SerializeToArray(out.bytes.data(), static_cast<int>(out.bytes.size()));
  pending_events_.push_back(std::move(out));
}

void Match::drop_pending_events(std::uint64_t account) {
  std::erase_if(pending_events_, [account](const Outgoing& out) { return out.account == account; });
}

void Match::queue_present(std::uint64_t account, const Player& other) {
  wire::GameEvent present;
  present.mutable_player_joined()->set_entity_id(other.entity_id);
  present.mutable_player_joined()->set_name(other.name);
  queue_event(account, present);
}

void Match::broadcast(const wire::GameEvent& event) {
  for (const Player& player : players_) {
    if (player.connected) queue_event(player.account, event);
  }
}

// --- the tick ---

int Match::tick(proto::TimeUs now) {
  const std::int64_t tick_start = profile_now();
  profile_ = TickProfile{};
  expire_disconnected(now);
  const int steps = clock_.advance(now);
  int run = 0;
  for (; run < steps && !ended(); ++run) {
    run_phase(&Match::apply_inputs, profile_.apply_inputs_ms);
    simulate_step();
  }
  ticks_since_snapshot_ += run;
  if (run > 0 && ticks_since_snapshot_ >= snapshot_interval_ticks_) {
    ticks_since_snapshot_ = 0;
    profile_.snapshot = true;
    run_phase(&Match::build_snapshots, profile_.snapshots_ms);
  }
  run_phase(&Match::send, profile_.send_ms);
  profile_.steps = run;
  profile_.total_ms = elapsed_ms(tick_start);
  counters_.steps += static_cast<std::uint64_t>(run);
  counters_.overruns = clock_.overruns();
  counters_.dropped_steps = clock_.dropped_steps();
  return run;
}

void Match::simulate_step() {
  run_phase(&Match::check_inputs, profile_.rules_ms);
  run_phase(&Match::update_rules, profile_.rules_ms);
  run_phase(&Match::move_players, profile_.movement_ms);
  run_phase(&Match::fire_weapons, profile_.combat_ms);
  run_phase(&Match::step_physics, profile_.physics_ms);
  run_phase(&Match::resolve_projectiles, profile_.combat_ms);
  run_phase(&Match::apply_hazards, profile_.combat_ms);
  run_phase(&Match::take_pickups, profile_.combat_ms);
  run_phase(&Match::record_history, profile_.history_ms);
  run_phase(&Match::record_step, profile_.history_ms);
}

void Match::run_phase(void (Match::*phase)(), double& ms) {
  const std::int64_t start = profile_now();
  (this->*phase)();
  ms += elapsed_ms(start);
}

bool Match::poll_outbox(Outgoing& out) {
  if (outbox_read_ >= outbox_.size()) {
    outbox_.clear();
    outbox_read_ = 0;
    return false;
  }
  out = std::move(outbox_[outbox_read_++]);
  return true;
}

std::int64_t Match::profile_now() const {
  return profile_clock_ ? profile_clock_() : 0;
}

double Match::elapsed_ms(std::int64_t since_ns) const {
  return static_cast<double>(profile_now() - since_ns) / 1e6;
}

// --- reading ---

int Match::connected_count() const {
  return static_cast<int>(std::count_if(players_.begin(), players_.end(),
                                        [](const Player& player) { return player.connected; }));
}

Match::Player* Match::find_entity(std::uint32_t entity_id) {
  const auto at = std::lower_bound(
      players_.begin(), players_.end(), entity_id,
      [](const Player& player, std::uint32_t id) { return player.entity_id < id; });
  return at != players_.end() && at->entity_id == entity_id ? &*at : nullptr;
}

std::vector<PlayerScore> Match::scoreboard() const {
  std::vector<PlayerScore> out = departed_;
  for (const Player& player : players_) out.push_back(player.score);
  std::sort(out.begin(), out.end(),
            [](const PlayerScore& a, const PlayerScore& b) { return a.entity_id < b.entity_id; });
  return out;
}

std::optional<Match::PlayerView> Match::player_view(std::uint64_t account) const {
  const Player* player = find(account);
  if (!player) return std::nullopt;
  return PlayerView{player->vitals, player->alive, player->team,
                    player->weapon, player->ammo,  player->violations};
}

std::optional<std::uint32_t> Match::entity_of(std::uint64_t account) const {
  const Player* player = find(account);
  if (!player) return std::nullopt;
  return player->entity_id;
}

std::span<const proto::EntityState> Match::entity_states() const {
  return states_at(tick_);
}

std::span<const proto::EntityState> Match::states_at(std::uint32_t tick) const {
  const HistoryEntry& entry = history_[tick % history_.size()];
  if (tick == 0 || entry.tick != tick) return {};
  return entry.states;
}

}  // namespace ricochet::server
