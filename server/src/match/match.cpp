/// A match's players, untrusted payloads, chat and the tick's table of contents (match.h). The
/// phases themselves are in match_phases.cpp.

#include "ricochet/server/match.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "ricochet/physics/scene_profile.h"

namespace ricochet::server {

namespace {

std::string range_error(const char* field, const char* range, long long value) {
  return std::string("match ") + field + " must be " + range + ", got " + std::to_string(value);
}

/// Printable UTF-8: well-formed sequences (no overlongs, surrogates or values past U+10FFFF)
/// and no C0 or C1 control characters.
bool is_printable_utf8(std::string_view text) {
  std::size_t at = 0;
  while (at < text.size()) {
    const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[at + k]); };
    const unsigned char lead = byte(0);
    std::size_t length = 0;
    std::uint32_t code = 0;
    if (lead < 0x80) {
      length = 1;
      code = lead;
    } else if (lead >= 0xC2 && lead <= 0xDF) {
      length = 2;
      code = lead & 0x1Fu;
    } else if (lead >= 0xE0 && lead <= 0xEF) {
      length = 3;
      code = lead & 0x0Fu;
    } else if (lead >= 0xF0 && lead <= 0xF4) {
      length = 4;
      code = lead & 0x07u;
    } else {
      return false;
    }
    if (at + length > text.size()) return false;
    for (std::size_t k = 1; k < length; ++k) {
      if ((byte(k) & 0xC0u) != 0x80u) return false;
      code = (code << 6) | (byte(k) & 0x3Fu);
    }
    const std::uint32_t smallest[] = {0, 0, 0x80, 0x800, 0x10000};
    if (code < smallest[length] || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) {
      return false;
    }
    if (code < 0x20 || (code >= 0x7F && code < 0xA0)) return false;
    at += length;
  }
  return true;
}

}  // namespace

const char* name(JoinRefusal reason) {
  switch (reason) {
    case JoinRefusal::MatchFull:
      return "match_full";
    case JoinRefusal::InvalidName:
      return "invalid_name";
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

std::string MatchConfig::validate() const {
  if (name.empty() || name.size() > 32 || !is_printable_utf8(name)) {
    return "match name must be 1..32 bytes of printable UTF-8, got '" + name + "'";
  }
  if (max_players < 1 || max_players > 64) return range_error("max_players", "1..64", max_players);
  if (std::string error = tick.validate(); !error.empty()) return "match " + error;
  if (snapshot_rate_hz < 1 || snapshot_rate_hz > tick.rate_hz) {
    return "match snapshot_rate_hz must be 1..tick rate_hz (" + std::to_string(tick.rate_hz) +
           "), got " + std::to_string(snapshot_rate_hz);
  }
  if (snapshot_budget_bytes < 128 || snapshot_budget_bytes > 1100) {
    return range_error("snapshot_budget_bytes", "128..1100",
                       static_cast<long long>(snapshot_budget_bytes));
  }
  if (reconnect_grace_us < 0 || reconnect_grace_us > 300 * proto::kMicrosPerSecond) {
    return range_error("reconnect_grace_us", "0..300000000", reconnect_grace_us);
  }
  if (history_ticks < 1 || history_ticks > 1024) {
    return range_error("history_ticks", "1..1024", history_ticks);
  }
  if (std::string error = movement.validate(); !error.empty()) return "match " + error;
  if (std::string error = input.validate(); !error.empty()) return "match " + error;
  return {};
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
  if (std::string error = spec.validate(); !error.empty()) {
    return "match quantization (with the bounds of map " + map.name + "): " + error;
  }
  physics::Result<physics::World> world =
      physics::World::create(physics::profiles::arena_players());
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
      world_(std::move(world)),
      clock_(config.tick, now),
      profile_clock_(std::move(profile_clock)),
      history_(static_cast<std::size_t>(config.history_ticks)) {
  for (const MapSpawn& spawn : map.spawns) spawns_.push_back(spawn.position_m);
  bounds_max_y_m_ = map.bounds_max_m.y() - player_body_def(physics::Vec3::Zero()).radius;
  snapshot_interval_ticks_ = std::max(
      1, static_cast<int>(std::lround(double(config.tick.rate_hz) / config.snapshot_rate_hz)));
  ticks_since_snapshot_ = snapshot_interval_ticks_;  // the first step sends one
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
    drop_pending_events(account);  // meant for the old connection
    ++counters_.players_reconnected;
    for (const Player& other : players_) {
      if (other.account != account) queue_present(account, other);
    }
    joined.mutable_player_joined()->set_entity_id(player->entity_id);
    joined.mutable_player_joined()->set_name(player->name);
    joined.mutable_player_joined()->set_reconnected(true);
    broadcast(joined);
    return Joined{player->entity_id, true};
  }
  if (player_count() >= config_.max_players) return refuse(JoinRefusal::MatchFull);

  const physics::Result<physics::BodyId> body = world_.create_body(player_body_def(choose_spawn()));
  assert(body.ok());  // a valid definition in a world far below its body limit
  Player player;
  player.account = account;
  player.name = std::string(name);
  player.entity_id = next_entity_id_++;
  player.body = body.value();
  player.inputs = InputBuffer(config_.input);
  player.snapshots = std::make_unique<proto::SnapshotEncoder>(config_.quantization);
  // Everyone already here, to the newcomer; then the newcomer to everyone (itself included).
  for (const Player& other : players_) queue_present(account, other);
  const Joined result{player.entity_id, false};
  joined.mutable_player_joined()->set_entity_id(player.entity_id);
  joined.mutable_player_joined()->set_name(player.name);
  players_.push_back(std::move(player));
  broadcast(joined);
  ++counters_.players_joined;
  return result;
}

physics::Vec3 Match::choose_spawn() {
  // Round robin over the spawns, skipping one a player stands on. When every spawn is taken
  // (more players than spawns), the same points one player height up, and so on: the newcomer
  // drops onto the floor or onto whoever is there.
  const physics::Real clearance =
      2 * player_body_def(physics::Vec3::Zero()).radius + physics::Real(0.1);
  const auto is_free = [&](const physics::Vec3& point) {
    return std::none_of(players_.begin(), players_.end(), [&](const Player& player) {
      return (world_.body_state(player.body).value().position - point).norm() < clearance;
    });
  };
  for (int level = 0;; ++level) {
    const physics::Vec3 lift(0, clearance * physics::Real(level), 0);
    bool inside = false;
    for (std::size_t tried = 0; tried < spawns_.size(); ++tried) {
      const std::size_t index = (next_spawn_ + tried) % spawns_.size();
      const physics::Vec3 point = spawns_[index] + lift;
      if (point.y() > bounds_max_y_m_) continue;
      inside = true;
      if (is_free(point)) {
        next_spawn_ = (index + 1) % spawns_.size();
        return point;
      }
    }
    if (!inside) break;  // above the bounds everywhere: share a spawn
  }
  const physics::Vec3 point = spawns_[next_spawn_];
  next_spawn_ = (next_spawn_ + 1) % spawns_.size();
  return point;
}

void Match::disconnect(std::uint64_t account, proto::TimeUs now) {
  Player* player = find(account);
  if (!player || !player->connected) return;
  player->connected = false;
  player->disconnected_at = now;
  player->inputs.reset();  // the entity stands still while away
  player->applied = PlayerInput{};
  player->snapshots.reset();
  drop_pending_events(account);
}

bool Match::leave(std::uint64_t account) {
  for (std::size_t k = 0; k < players_.size(); ++k) {
    if (players_[k].account == account) {
      remove_player(k, wire::LEAVE_REASON_LEFT);
      ++counters_.players_left;
      return true;
    }
  }
  return false;
}

void Match::remove_player(std::size_t index, wire::LeaveReason reason) {
  const Player& player = players_[index];
  [[maybe_unused]] const physics::Status destroyed = world_.destroy_body(player.body);
  assert(destroyed.ok());
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
      remove_player(k, wire::LEAVE_REASON_TIMED_OUT);
      ++counters_.players_timed_out;
    }
  }
}

void Match::receive(std::uint64_t account, std::span<const std::uint8_t> payload) {
  const auto drop = [this](InputDrop reason) {
    ++counters_.input_drops[static_cast<std::size_t>(reason)];
  };
  Player* player = find(account);
  if (!player || !player->connected) return drop(InputDrop::UnknownPlayer);
  wire::ClientPayload message;
  if (payload.size() > kMaxClientPayloadBytes ||
      !message.ParseFromArray(payload.data(), static_cast<int>(payload.size()))) {
    return drop(InputDrop::MalformedPayload);
  }
  if (static_cast<std::size_t>(message.inputs_size()) > kMaxInputsPerPayload) {
    return drop(InputDrop::TooManyInputs);
  }
  ++counters_.payloads_received;
  for (const wire::Input& in : message.inputs()) {
    PlayerInput input;
    InputDrop reason{};
    if (validate_input(in, input, reason)) {
      player->inputs.offer(input, counters_.input_drops);
    } else {
      drop(reason);
    }
  }
  if (message.ack_snapshot_tick() != 0) player->snapshots->acknowledge(message.ack_snapshot_tick());
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
  for (int step = 0; step < steps; ++step) {
    run_phase(&Match::apply_inputs, profile_.apply_inputs_ms);
    run_phase(&Match::move_players, profile_.movement_ms);
    run_phase(&Match::step_physics, profile_.physics_ms);
    run_phase(&Match::record_history, profile_.history_ms);
  }
  ticks_since_snapshot_ += steps;
  if (steps > 0 && ticks_since_snapshot_ >= snapshot_interval_ticks_) {
    ticks_since_snapshot_ = 0;
    profile_.snapshot = true;
    run_phase(&Match::build_snapshots, profile_.snapshots_ms);
  }
  run_phase(&Match::send, profile_.send_ms);
  profile_.steps = steps;
  profile_.total_ms = elapsed_ms(tick_start);
  counters_.steps += static_cast<std::uint64_t>(steps);
  counters_.overruns = clock_.overruns();
  counters_.dropped_steps = clock_.dropped_steps();
  return steps;
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
