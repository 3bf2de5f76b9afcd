/// A match's players, untrusted payloads, chat and the tick's table of contents (match.h). The
/// parts it holds and the phases of a step are in the headers match_parts.h lists.

#include "ricochet/server/match.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "match_movement.h"
#include "match_parts.h"
#include "ricochet/physics/scene_profile.h"
#include "ricochet/proto/chat_text.h"
#include "ricochet/server/match_record.h"

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
  return Match(std::make_unique<MatchParts>(resolved, map, std::move(world).value(), now,
                                            std::move(profile_clock)));
}

MatchParts::MatchParts(const MatchConfig& config, const Map& map, physics::World world,
                       proto::TimeUs now, ProfileClock profile_clock)
    : config(config),
      map(map),
      world(std::move(world)),
      clock(config.tick, now),
      profile_clock(std::move(profile_clock)),
      rules(config.rules.seed),
      combat(config.lag, config.tick.rate_hz),
      history(config.history_ticks),
      snapshots(config.snapshot_cache_layers) {
  for (const MapPickup& spot : map.pickups) rules.pickups.push_back(PickupState{spot, true, 0});
  snapshots.interval_ticks = std::max(
      1, static_cast<int>(std::lround(double(config.tick.rate_hz) / config.snapshot_rate_hz)));
  snapshots.ticks_since = snapshots.interval_ticks;  // the first step sends one
  if (config.record) {
    RecordingHeader header;
    header.server_version = "ricochet-match 1";
    for (const MapFile& file : map.files) header.map_files.push_back({file.path, file.text});
    header.config = encode_match_config(config);
    header.seed = config.rules.seed;
    header.hash_interval_ticks = static_cast<std::uint32_t>(config.hash_interval_ticks);
    header.tick_rate_hz = static_cast<std::uint32_t>(config.tick.rate_hz);
    recorder.writer =
        std::make_unique<RecordingWriter>(std::move(header), config.max_recording_bytes);
  }
}

Match::Match(std::unique_ptr<MatchParts> parts) : parts_(std::move(parts)) {}
Match::Match(Match&&) noexcept = default;
Match& Match::operator=(Match&&) noexcept = default;
Match::~Match() = default;

void Match::set_log(MatchLog log) {
  parts_->log = std::move(log);
}

void Match::set_live_feed(std::shared_ptr<LiveFeed> feed) {
  parts_->live = LiveTap{};
  parts_->live.feed = std::move(feed);
}

namespace {

std::int64_t profile_now(const ProfileClock& clock) {
  return clock ? clock() : 0;
}

double elapsed_ms(const ProfileClock& clock, std::int64_t since_ns) {
  return static_cast<double>(profile_now(clock) - since_ns) / 1e6;
}

/// Runs a phase, adding its time on the profile clock to a TickProfile field (ms).
struct PhaseTimer {
  const ProfileClock& clock;

  template <typename Phase>
  void operator()(double& ms, Phase&& phase) const {
    const std::int64_t start = profile_now(clock);
    phase();
    ms += elapsed_ms(clock, start);
  }
};

// --- players ---

/// Takes the player at `index` out of the match: its body, its pending events; keeps its score
/// when it counts in the record; tells everyone why.
void remove_player(std::size_t index, wire::LeaveReason reason, physics::World& world,
                   Roster& roster, Mailbox& mailbox) {
  const Player& player = roster.players[index];
  if (!player.body.is_null()) {
    [[maybe_unused]] const physics::Status destroyed = world.destroy_body(player.body);
    assert(destroyed.ok());
  }
  if (counts_in_record(player.score)) {
    roster.departed.push_back(player.score);
  }
  wire::GameEvent left;
  left.mutable_player_left()->set_entity_id(player.entity_id);
  left.mutable_player_left()->set_name(player.name);
  left.mutable_player_left()->set_reason(reason);
  const std::uint64_t account = player.account;
  roster.players.erase(roster.players.begin() + static_cast<std::ptrdiff_t>(index));
  mailbox.drop(account);
  mailbox.broadcast(roster, left);
}

/// Removes a player whose reconnect grace ran out.
void time_out(std::size_t index, MatchParts& m) {
  m.recorder.note(
      RecordedEvent{RecordedEventKind::TimedOut, m.roster.players[index].account, {}, 0});
  remove_player(index, wire::LEAVE_REASON_TIMED_OUT, m.world, m.roster, m.mailbox);
  ++m.counters.players_timed_out;
}

void expire_disconnected(proto::TimeUs now, MatchParts& m) {
  for (std::size_t k = m.roster.players.size(); k-- > 0;) {
    const Player& player = m.roster.players[k];
    if (!player.connected && now - player.disconnected_at >= m.config.reconnect_grace_us) {
      time_out(k, m);
    }
  }
}

}  // namespace

std::variant<Joined, JoinRefusal> Match::connect(std::uint64_t account, std::string_view name) {
  MatchParts& m = *parts_;
  const auto refuse = [&m](JoinRefusal reason) {
    ++m.counters.join_refusals[static_cast<std::size_t>(reason)];
    return reason;
  };
  if (ended()) return refuse(JoinRefusal::MatchEnded);
  if (name.empty() || name.size() > kMaxPlayerNameBytes || !is_printable_utf8(name)) {
    return refuse(JoinRefusal::InvalidName);
  }
  Game game = m.game();
  wire::GameEvent joined;
  if (Player* player = m.roster.find(account)) {
    // Back within the grace, or a new connection replacing one still open: same entity, a new
    // client (sequence from 1, no snapshot baseline).
    player->connected = true;
    player->name = std::string(name);
    player->inputs.reset();
    player->applied = PlayerInput{};
    player->snapshots = std::make_unique<proto::SnapshotEncoder>(m.config.quantization);
    player->snapshot_ack = 0;
    m.mailbox.drop(account);  // meant for the old connection
    ++m.counters.players_reconnected;
    m.recorder.note(RecordedEvent{RecordedEventKind::Connect, account, std::string(name), 0});
    for (const Player& other : m.roster.players) {
      if (other.account != account) m.mailbox.queue_present(account, other);
    }
    queue_arrival(game, account);
    joined.mutable_player_joined()->set_entity_id(player->entity_id);
    joined.mutable_player_joined()->set_name(player->name);
    joined.mutable_player_joined()->set_reconnected(true);
    m.mailbox.broadcast(m.roster, joined);
    return Joined{player->entity_id, true};
  }
  if (player_count() >= m.config.max_players) return refuse(JoinRefusal::MatchFull);

  m.recorder.note(RecordedEvent{RecordedEventKind::Connect, account, std::string(name), 0});
  Player player;
  player.account = account;
  player.name = std::string(name);
  player.entity_id = m.roster.new_entity_id();
  player.inputs = InputBuffer(m.config.input);
  player.snapshots = std::make_unique<proto::SnapshotEncoder>(m.config.quantization);
  player.team = balanced_team(game);
  // A player coming back after leaving keeps what it scored.
  std::vector<PlayerScore>& departed = m.roster.departed;
  const auto before =
      std::find_if(departed.begin(), departed.end(),
                   [account](const PlayerScore& s) { return s.account == account; });
  if (before != departed.end()) {
    player.score = *before;
    departed.erase(before);
  }
  player.score.account = account;
  player.score.name = player.name;
  player.score.entity_id = player.entity_id;
  player.score.team = player.team;
  // Everyone already here, to the newcomer; then the newcomer to everyone (itself included).
  for (const Player& other : m.roster.players) m.mailbox.queue_present(account, other);
  queue_arrival(game, account);
  const Joined result{player.entity_id, false};
  joined.mutable_player_joined()->set_entity_id(player.entity_id);
  joined.mutable_player_joined()->set_name(player.name);
  m.roster.players.push_back(std::move(player));
  m.mailbox.broadcast(m.roster, joined);
  spawn(game, m.roster.players.back());
  ++m.counters.players_joined;
  return result;
}

void Match::disconnect(std::uint64_t account, proto::TimeUs now) {
  MatchParts& m = *parts_;
  Player* player = m.roster.find(account);
  if (!player || !player->connected) return;
  m.recorder.note(RecordedEvent{RecordedEventKind::Disconnect, account, {}, 0});
  player->connected = false;
  player->disconnected_at = now;
  player->inputs.reset();  // the entity stands still while away
  player->applied = PlayerInput{};
  player->snapshots.reset();
  player->snapshot_ack = 0;
  m.mailbox.drop(account);
}

bool Match::leave(std::uint64_t account) {
  MatchParts& m = *parts_;
  for (std::size_t k = 0; k < m.roster.players.size(); ++k) {
    if (m.roster.players[k].account == account) {
      m.recorder.note(RecordedEvent{RecordedEventKind::Leave, account, {}, 0});
      remove_player(k, wire::LEAVE_REASON_LEFT, m.world, m.roster, m.mailbox);
      ++m.counters.players_left;
      return true;
    }
  }
  return false;
}

void Match::receive(std::uint64_t account, std::span<const std::uint8_t> payload) {
  MatchParts& m = *parts_;
  const auto drop = [&m](InputDrop reason) {
    ++m.counters.input_drops[static_cast<std::size_t>(reason)];
  };
  Player* player = m.roster.find(account);
  if (!player || !player->connected) return drop(InputDrop::UnknownPlayer);
  wire::ClientPayload& message = m.incoming;
  if (payload.size() > proto::kMaxClientPayloadBytes ||
      !message.ParseFromArray(payload.data(), static_cast<int>(payload.size()))) {
    return drop(InputDrop::MalformedPayload);
  }
  if (static_cast<std::size_t>(message.inputs_size()) > proto::kMaxInputsPerPayload) {
    return drop(InputDrop::TooManyInputs);
  }
  ++m.counters.payloads_received;
  // Input rate: a client sends one input per tick; a window of one second may bring more
  // (input_rate_limit: clock drift, bursts after a stall). Beyond that the inputs are refused: a
  // sped-up client gains nothing and is counted.
  const std::uint32_t window = static_cast<std::uint32_t>(m.config.tick.rate_hz);
  if (m.tick - player->input_window_start >= window) {
    player->input_window_start = m.tick;
    player->inputs_in_window = 0;
  }
  const auto allowed = static_cast<std::uint32_t>(input_rate_limit(m.config.tick.rate_hz));
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
      note_violation(*player, Violation::InputRate, m.violations());
      continue;
    }
    ++player->inputs_in_window;
    player->inputs.offer(input, m.counters.input_drops);
  }
  // Only the newest acknowledgement counts (SnapshotEncoder::acknowledge ignores older ones).
  player->snapshot_ack = std::max(player->snapshot_ack, message.ack_snapshot_tick());
}

void Match::set_latency(std::uint64_t account, proto::TimeUs one_way_us) {
  if (Player* player = parts_->roster.find(account)) {
    player->latency_us = std::clamp<proto::TimeUs>(one_way_us, 0, proto::kMicrosPerSecond);
  }
}

std::optional<ChatDrop> Match::chat(std::uint64_t account, std::string_view text) {
  MatchParts& m = *parts_;
  std::optional<ChatDrop> refusal;
  const Player* player = m.roster.find(account);
  if (!player || !player->connected)
    refusal = ChatDrop::NotInMatch;
  else if (const auto problem = proto::check_chat_text(text))
    refusal = problem->problem == proto::ChatTextProblem::Empty     ? ChatDrop::Empty
              : problem->problem == proto::ChatTextProblem::TooLong ? ChatDrop::TooLong
                                                                    : ChatDrop::InvalidText;
  if (refusal) {
    ++m.counters.chat_drops[static_cast<std::size_t>(*refusal)];
    return refusal;
  }
  wire::GameEvent event;
  wire::ChatMessage& line = *event.mutable_chat();
  line.set_entity_id(player->entity_id);
  line.set_name(player->name);
  line.set_text(std::string(text));
  m.mailbox.broadcast(m.roster, event, proto::Delivery::Droppable);
  ++m.counters.chat_messages;
  return std::nullopt;
}

void Match::end(wire::MatchEndReason reason) {
  MatchParts& m = *parts_;
  if (ended()) return;
  Game game = m.game();
  finish(game, reason);
  m.snapshots.payload_count = 0;  // no snapshot goes with it
  send(m.snapshots, m.mailbox, m.counters);
  // The ended phase's frame, at the last step's time (or the first step's, before any).
  const proto::TimeUs at = m.live.last_tick_us != 0 ? m.live.last_tick_us : m.clock.next_step_at();
  publish_live_frame(at, m.config, m.tick, m.roster, m.combat, m.rules, m.live);
}

// --- the tick ---

int Match::tick(proto::TimeUs now) {
  MatchParts& m = *parts_;
  const PhaseTimer timed{m.profile_clock};
  const std::int64_t tick_start = profile_now(m.profile_clock);
  m.profile = TickProfile{};
  expire_disconnected(now, m);
  const int steps = m.clock.advance(now);
  int run = 0;
  for (; run < steps && !ended(); ++run) {
    timed(m.profile.apply_inputs_ms,
          [&] { apply_inputs(m.roster, m.recorder.step_inputs, m.counters); });
    simulate_step();
  }
  m.snapshots.ticks_since += run;
  if (run > 0 && m.snapshots.ticks_since >= m.snapshots.interval_ticks) {
    m.snapshots.ticks_since = 0;
    m.profile.snapshot = true;
    timed(m.profile.snapshots_ms, [&] {
      build_snapshots(m.tick, m.history.states_at(m.tick), m.config.quantization,
                      m.config.snapshot_budget_bytes, m.roster, m.snapshots);
    });
  }
  timed(m.profile.send_ms, [&] { send(m.snapshots, m.mailbox, m.counters); });
  if (run > 0) {
    publish_live_frame(now, m.config, m.tick, m.roster, m.combat, m.rules, m.live);
  }
  m.profile.steps = run;
  m.profile.total_ms = elapsed_ms(m.profile_clock, tick_start);
  m.counters.steps += static_cast<std::uint64_t>(run);
  m.counters.overruns = m.clock.overruns();
  m.counters.dropped_steps = m.clock.dropped_steps();
  return run;
}

void Match::simulate_step() {
  MatchParts& m = *parts_;
  const PhaseTimer timed{m.profile_clock};
  const double step_s = m.clock.step_s();
  Game game = m.game();
  timed(m.profile.rules_ms,
        [&] { check_inputs(m.config.weapons, step_s, m.roster, m.violations()); });
  timed(m.profile.rules_ms, [&] { update_rules(game); });
  timed(m.profile.movement_ms, [&] { move_players(m.config.movement, step_s, m.roster, m.world); });
  timed(m.profile.combat_ms, [&] { fire_weapons(game); });
  timed(m.profile.physics_ms, [&] { step_physics(step_s, m.world, m.tick); });
  timed(m.profile.combat_ms, [&] { resolve_projectiles(game); });
  timed(m.profile.combat_ms, [&] { apply_hazards(game); });
  timed(m.profile.combat_ms, [&] { take_pickups(game); });
  timed(m.profile.history_ms,
        [&] { record_history(m.tick, m.world, m.roster, m.combat, m.history); });
  timed(m.profile.history_ms, [&] {
    const bool hashed = m.recorder.hash_due(m.tick, m.config.hash_interval_ticks);
    record_step(m.tick, hashed ? std::optional(m.state_hash()) : std::nullopt, m.recorder,
                m.counters);
  });
}

bool Match::poll_outbox(Outgoing& out) {
  return parts_->mailbox.poll(out);
}

// --- replay ---

void Match::apply(const RecordedEvent& event) {
  MatchParts& m = *parts_;
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
      for (std::size_t k = 0; k < m.roster.players.size(); ++k) {
        if (m.roster.players[k].account == event.account) {
          time_out(k, m);
          break;
        }
      }
      break;
    case RecordedEventKind::End:
      end(static_cast<wire::MatchEndReason>(event.end_reason));
      break;
  }
  m.mailbox.clear();  // nobody listens to a replay
}

void Match::step_recorded(std::span<const RecordedInput> inputs) {
  MatchParts& m = *parts_;
  if (ended()) return;
  m.recorder.step_inputs.assign(inputs.begin(), inputs.end());
  for (Player& player : m.roster.players) player.applied = PlayerInput{};
  for (const RecordedInput& input : inputs) {
    if (Player* player = m.roster.find_entity(input.entity_id)) {
      player->applied = input.input;
      player->latency_us = input.latency_us;
    }
  }
  simulate_step();
  ++m.counters.steps;
  m.mailbox.pending.clear();
}

std::vector<std::uint8_t> Match::take_recording_chunks() {
  const std::unique_ptr<RecordingWriter>& writer = parts_->recorder.writer;
  return writer ? writer->take_completed() : std::vector<std::uint8_t>{};
}

std::vector<std::uint8_t> Match::take_recording() {
  std::unique_ptr<RecordingWriter>& writer = parts_->recorder.writer;
  if (!writer) return {};
  std::vector<std::uint8_t> bytes = writer->finish();
  writer.reset();
  return bytes;
}

void Match::observe_events(std::function<void(const wire::GameEvent&)> observer) {
  parts_->mailbox.observer = std::move(observer);
}

std::uint64_t Match::state_hash() const {
  return parts_->state_hash();
}

// --- reading ---

bool Match::ended() const {
  return parts_->rules.ended();
}
wire::MatchEndReason Match::end_reason() const {
  return parts_->rules.end_reason;
}
std::size_t Match::outbox_size() const {
  return parts_->mailbox.size();
}
proto::TimeUs Match::next_tick_at() const {
  return parts_->clock.next_step_at();
}
std::uint32_t Match::id() const {
  return parts_->config.id;
}
const std::string& Match::name() const {
  return parts_->config.name;
}
const std::string& Match::map_name() const {
  return parts_->map.name;
}
const MatchConfig& Match::config() const {
  return parts_->config;
}
std::uint32_t Match::tick_number() const {
  return parts_->tick;
}
MatchPhase Match::phase() const {
  return parts_->rules.phase;
}
std::uint32_t Match::phase_ends_tick() const {
  return parts_->rules.phase_ends_tick;
}
int Match::player_count() const {
  return static_cast<int>(parts_->roster.players.size());
}
int Match::connected_count() const {
  return parts_->roster.connected_count();
}
int Match::max_players() const {
  return parts_->config.max_players;
}
std::array<int, 3> Match::team_scores() const {
  return parts_->rules.team_scores;
}
const TickProfile& Match::profile() const {
  return parts_->profile;
}
const MatchCounters& Match::counters() const {
  return parts_->counters;
}
const physics::World& Match::world() const {
  return parts_->world;
}

std::vector<PlayerScore> Match::scoreboard() const {
  return parts_->roster.scoreboard();
}

std::optional<Match::PlayerView> Match::player_view(std::uint64_t account) const {
  const Player* player = parts_->roster.find(account);
  if (!player) return std::nullopt;
  return PlayerView{player->vitals, player->alive, player->team,
                    player->weapon, player->ammo,  player->violations};
}

std::optional<std::uint32_t> Match::entity_of(std::uint64_t account) const {
  const Player* player = parts_->roster.find(account);
  if (!player) return std::nullopt;
  return player->entity_id;
}

std::span<const proto::EntityState> Match::entity_states() const {
  return states_at(parts_->tick);
}

std::span<const proto::EntityState> Match::states_at(std::uint32_t tick) const {
  return parts_->history.states_at(tick);
}

}  // namespace ricochet::server
