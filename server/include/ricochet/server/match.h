#pragma once
/// A match: players, their inputs, movement on the physics core, the fixed tick and the
/// snapshots each player is sent. Socket-free and clock-free: the server hands it time, the
/// account's validated identity and the bytes that came, and drains the bytes to send from its
/// outbox. One thread owns a Match.
///
/// Lifecycle of a player (keyed by account id):
///   connect()     enters the match with a new entity at a spawn point, or comes back to its
///                 entity (within the reconnect grace, or replacing a connection still open);
///   disconnect()  the game connection is gone: the entity stays, without input, for the grace;
///   leave()       gone for good, at once;
///   tick()        removes players whose grace ran out.
/// Everyone connected gets a reliable PlayerJoined / PlayerLeft for each change, a newcomer one
/// PlayerJoined for every player already there, the MatchState and the pickups that are down.
///
/// The game (rules.h, weapons.h, combat.h, lag_compensation.h) is deterministic: the same config,
/// map, membership calls between steps and inputs per step give the same state bit for bit.
/// A recording (recording.h) keeps exactly those, and apply() + step_recorded() play them back.

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "ricochet/physics/world.h"
#include "ricochet/proto/clock.h"
#include "ricochet/proto/snapshot_codec.h"
#include "ricochet/server/combat.h"
#include "ricochet/server/input_buffer.h"
#include "ricochet/server/lag_compensation.h"
#include "ricochet/server/map.h"
#include "ricochet/server/match_config.h"
#include "ricochet/server/movement.h"
#include "ricochet/server/recording.h"
#include "ricochet/server/rules.h"
#include "ricochet/server/tick_clock.h"
#include "ricochet/server/tick_profile.h"
#include "ricochet/server/weapons.h"
#include "ricochet/wire/game.pb.h"

namespace ricochet::server {

// The bits of each entity's flags are proto/entity_flags.h's.
inline constexpr std::size_t kMaxChatBytes = 200;
inline constexpr std::size_t kMaxPlayerNameBytes = 32;

/// Why connect() refused a player.
enum class JoinRefusal : std::uint8_t {
  MatchFull,    ///< max_players seated (connected or within their grace)
  InvalidName,  ///< not 1..32 bytes of printable UTF-8
  MatchEnded,   ///< end() was called
};
inline constexpr std::size_t kJoinRefusalCount =
    static_cast<std::size_t>(JoinRefusal::MatchEnded) + 1;
const char* name(JoinRefusal reason);

struct Joined {
  std::uint32_t entity_id = 0;
  bool reconnected = false;  ///< came back to its entity
  friend bool operator==(const Joined&, const Joined&) = default;
};

/// Why chat() refused a line.
enum class ChatDrop : std::uint8_t {
  NotInMatch,  ///< the account is not connected to this match
  Empty,
  TooLong,      ///< more than kMaxChatBytes
  InvalidText,  ///< not UTF-8, or control characters
};
inline constexpr std::size_t kChatDropCount = static_cast<std::size_t>(ChatDrop::InvalidText) + 1;
const char* name(ChatDrop reason);

struct MatchCounters {
  std::uint64_t steps = 0;
  std::uint64_t overruns = 0;           ///< tick() calls that hit the catch-up cap (TickClock)
  std::uint64_t dropped_steps = 0;      ///< steps skipped by those
  std::uint64_t payloads_received = 0;  ///< ClientPayloads that parsed and were used
  std::uint64_t inputs_applied = 0;     ///< player-steps that had a fresh input
  std::uint64_t inputs_repeated = 0;    ///< player-steps that repeated the last one
  std::uint64_t snapshots_sent = 0;
  std::uint64_t snapshot_bytes = 0;  ///< serialised ServerPayloads
  std::uint64_t events_sent = 0;     ///< GameEvents, counted once per recipient
  std::uint64_t players_joined = 0;
  std::uint64_t players_reconnected = 0;
  std::uint64_t players_left = 0;
  std::uint64_t players_timed_out = 0;
  std::uint64_t chat_messages = 0;
  std::uint64_t shots_fired = 0;  ///< rifle rays, rockets and grenades
  std::uint64_t lag_compensated_shots = 0;
  std::uint64_t view_claims_clamped = 0;  ///< Input.view_tick outside the trusted window
  std::uint64_t hits = 0;                 ///< damage events on players
  std::uint64_t kills = 0;
  std::uint64_t explosions = 0;
  std::uint64_t respawns = 0;
  std::uint64_t pickups_taken = 0;
  std::uint64_t recording_bytes = 0;
  bool recording_truncated = false;  ///< max_recording_bytes reached: recording stopped
  std::array<std::uint64_t, kViolationCount> violations{};       ///< by Violation
  InputDropCounters input_drops{};                               ///< by InputDrop
  std::array<std::uint64_t, kChatDropCount> chat_drops{};        ///< by ChatDrop
  std::array<std::uint64_t, kJoinRefusalCount> join_refusals{};  ///< by JoinRefusal
};

/// Bytes for one player, to hand to its game connection.
struct Outgoing {
  std::uint64_t account = 0;
  /// true: a serialised GameEvent for the reliable-ordered channel; false: a serialised
  /// ServerPayload to send unreliably.
  bool reliable = false;
  std::vector<std::uint8_t> bytes;
};

/// A line for the server's log (rule violations, per player), from the match's thread.
using MatchLog = std::function<void(std::string_view line)>;

class Match {
 public:
  /// Builds the world from `map` (its static geometry, its bounds as the snapshots' bounds).
  /// Fails with a message naming the wrong config field or the map geometry physics refused.
  /// `now` starts the tick clock.
  static std::variant<Match, std::string> create(const MatchConfig& config, const Map& map,
                                                 proto::TimeUs now,
                                                 ProfileClock profile_clock = {});

  Match(Match&&) noexcept;
  Match& operator=(Match&&) noexcept;
  ~Match();

  void set_log(MatchLog log) { log_ = std::move(log); }

  // --- players ---
  /// The account's game connection is up (the transport checked its token). `name` is the
  /// account's name.
  std::variant<Joined, JoinRefusal> connect(std::uint64_t account, std::string_view name);
  /// The account's game connection is gone; its entity waits reconnect_grace_us from `now`.
  void disconnect(std::uint64_t account, proto::TimeUs now);
  /// The account leaves the match for good. False when it was not in it.
  bool leave(std::uint64_t account);
  /// A ClientPayload from the account's connection: untrusted bytes, validated, and dropped and
  /// counted by InputDrop when wrong.
  void receive(std::uint64_t account, std::span<const std::uint8_t> payload);
  /// The transport's latency estimate for the account: one way, µs (RTT / 2). Lag compensation
  /// rewinds by it (and it is recorded with every input).
  void set_latency(std::uint64_t account, proto::TimeUs one_way_us);
  /// A chat line from the account, echoed to every connected player. Returns why it was refused,
  /// or nothing when it was accepted.
  std::optional<ChatDrop> chat(std::uint64_t account, std::string_view text);

  /// Ends the match: every connected player gets a MatchEnded, put in the outbox at once (drain
  /// it before closing the connections); connect() refuses from now on. The match also ends by
  /// itself at its frag or time limit (rules.h).
  void end(wire::MatchEndReason reason);
  bool ended() const { return phase_ == MatchPhase::Ended; }
  wire::MatchEndReason end_reason() const { return end_reason_; }

  // --- the tick ---
  /// Runs the fixed steps due at `now`; after the last, builds and sends the snapshots when one
  /// is due. Returns the number of steps run. Drain the outbox after every call.
  int tick(proto::TimeUs now);
  /// Takes the next message to send, oldest first; false when the outbox is empty.
  bool poll_outbox(Outgoing& out);
  /// Messages poll_outbox still holds (to size the batch they go into).
  std::size_t outbox_size() const { return outbox_.size() - outbox_read_; }
  /// When the next step is due: sleep until then.
  proto::TimeUs next_tick_at() const { return clock_.next_step_at(); }

  // --- replay (recording.h) ---
  /// Plays back a membership change recorded before a step.
  void apply(const RecordedEvent& event);
  /// Runs one step with these inputs (players without one get the neutral input), as tick()
  /// would have with the inputs it applied; no snapshots are built.
  void step_recorded(std::span<const RecordedInput> inputs);
  /// The recording so far, finished (footer written); empty when config.record is off. The
  /// match keeps no recording after this.
  std::vector<std::uint8_t> take_recording();
  /// The hash recordings check: the world's state_hash() and every game rule's state (health,
  /// armour, ammunition, scores, timers, pickups, projectiles, the generator).
  std::uint64_t state_hash() const;

  // --- reading ---
  std::uint32_t id() const { return config_.id; }
  const std::string& name() const { return config_.name; }
  const std::string& map_name() const { return map_name_; }
  const MatchConfig& config() const { return config_; }
  std::uint32_t tick_number() const { return tick_; }
  MatchPhase phase() const { return phase_; }
  int player_count() const { return static_cast<int>(players_.size()); }  ///< seated
  int connected_count() const;
  int max_players() const { return config_.max_players; }
  std::optional<std::uint32_t> entity_of(std::uint64_t account) const;
  /// Every seated player, and everyone who left after playing while the match was running, by
  /// entity.
  std::vector<PlayerScore> scoreboard() const;
  /// Team scores by wire::Team (index 1 red, 2 blue; 0 unused), team deathmatch.
  std::array<int, 3> team_scores() const { return team_scores_; }
  /// A seated player's vitals and weapon, for tests and tools.
  struct PlayerView {
    Vitals vitals;
    bool alive = false;
    Team team = Team::None;
    WeaponKind weapon = WeaponKind::Rifle;
    std::array<int, kWeaponCount> ammo{};
    std::array<std::uint64_t, kViolationCount> violations{};
  };
  std::optional<PlayerView> player_view(std::uint64_t account) const;
  /// The entity states after the last step (players, rockets, grenades), sorted by id.
  std::span<const proto::EntityState> entity_states() const;
  /// The entity states after step `tick` while it is in the history ring (the last
  /// history_ticks steps), sorted by id; empty otherwise.
  std::span<const proto::EntityState> states_at(std::uint32_t tick) const;
  const TickProfile& profile() const { return profile_; }
  const MatchCounters& counters() const { return counters_; }
  const physics::World& world() const { return world_; }

 private:
  struct Player {
    std::uint64_t account = 0;
    std::string name;
    std::uint32_t entity_id = 0;
    physics::BodyId body;  ///< null while dead
    bool connected = true;
    proto::TimeUs disconnected_at = 0;
    bool grounded = false;
    InputBuffer inputs;
    PlayerInput applied;                                ///< this step's input
    std::unique_ptr<proto::SnapshotEncoder> snapshots;  ///< per connection, none while away
    /// The newest snapshot tick the client acknowledged since the last snapshot (0: none),
    /// handed to `snapshots` when the next one is built: the encoder stays cold between ticks.
    std::uint32_t snapshot_ack = 0;
    proto::TimeUs latency_us = 0;  ///< one way

    // --- the game ---
    Team team = Team::None;
    Vitals vitals;
    bool alive = true;
    std::uint32_t life = 0;                            ///< bumps at every spawn (lag compensation)
    std::uint32_t respawn_tick = 0;                    ///< while dead
    std::uint32_t protected_until = 0;                 ///< no damage before this tick
    physics::Vec3 position_m = physics::Vec3::Zero();  ///< after the last step (or at death)
    physics::Vec3 velocity_mps = physics::Vec3::Zero();
    WeaponKind weapon = WeaponKind::Rifle;
    std::array<int, kWeaponCount> ammo{};
    std::uint32_t next_fire_tick = 0;  ///< the weapon is ready at this tick
    std::uint32_t previous_buttons = 0;
    float aim_yaw_rad = 0, aim_pitch_rad = 0;  ///< the aim the checks accepted
    bool aimed = false;                        ///< aim_* hold a previous aim
    PlayerScore score;
    std::array<std::uint64_t, kViolationCount> violations{};
    std::uint32_t input_window_start = 0;  ///< tick the input-rate window began
    std::uint32_t inputs_in_window = 0;    ///< new inputs offered in it
  };
  /// A rocket or grenade in flight.
  struct Projectile {
    std::uint32_t entity_id = 0;
    WeaponKind weapon = WeaponKind::RocketLauncher;
    std::uint32_t owner_entity = 0;
    Team owner_team = Team::None;
    physics::ProjectileId rocket;    ///< a rocket's
    physics::BodyId grenade;         ///< a grenade's
    std::uint32_t expires_tick = 0;  ///< fuse (grenade) or longest flight (rocket)
    physics::Vec3 position_m = physics::Vec3::Zero();
    physics::Vec3 velocity_mps = physics::Vec3::Zero();
  };
  struct PickupState {
    MapPickup spot;
    bool available = true;
    std::uint32_t respawn_tick = 0;
  };
  struct HistoryEntry {
    std::uint32_t tick = 0;
    std::vector<proto::EntityState> states;  ///< sorted by id
  };

  Match(const MatchConfig& config, physics::World world, const Map& map, proto::TimeUs now,
        ProfileClock profile_clock);

  // One step (simulate_step), the table of contents: every phase is deterministic.
  void simulate_step();
  // The phases of a step and of a snapshot (match_phases.cpp).
  void apply_inputs();
  void check_inputs();  // match_checks.cpp
  void update_rules();  // match_rules.cpp
  void move_players();
  void fire_weapons();  // match_combat.cpp
  void step_physics();
  void resolve_projectiles();  // match_combat.cpp
  void apply_hazards();        // match_combat.cpp: kill volumes, bounds
  void take_pickups();         // match_combat.cpp
  void record_history();
  void record_step();  // match_recording.cpp
  void build_snapshots();
  void send();

  /// Runs one phase, adding its time to `ms`.
  void run_phase(void (Match::*phase)(), double& ms);
  Player* find(std::uint64_t account);
  const Player* find(std::uint64_t account) const;
  Player* find_entity(std::uint32_t entity_id);
  void remove_player(std::size_t index, wire::LeaveReason reason);
  /// Removes a player whose reconnect grace ran out.
  void time_out(std::size_t index);
  void expire_disconnected(proto::TimeUs now);
  void broadcast(const wire::GameEvent& event);
  void queue_event(std::uint64_t account, const wire::GameEvent& event);
  /// Forgets the events queued for `account`: its connection is gone or replaced.
  void drop_pending_events(std::uint64_t account);
  /// Tells `account` that `other` is in the match (a PlayerJoined).
  void queue_present(std::uint64_t account, const Player& other);
  /// Tells a newcomer the state of the match: the phase and the pickups that are down.
  void queue_arrival(std::uint64_t account);
  double elapsed_ms(std::int64_t since_ns) const;
  std::int64_t profile_now() const;
  void note_violation(Player& player, Violation violation);

  // The rules (match_rules.cpp).
  std::uint32_t ticks_of(float seconds) const;
  Team balanced_team() const;
  /// The spawn farthest from living enemies, among those of the player's team.
  const MapSpawn& choose_spawn(const Player& player) const;
  /// Puts a player (back) into play at a spawn: a new body, full health, the start weapons.
  void spawn(Player& player);
  void enter_phase(MatchPhase phase);
  void start_running();
  wire::GameEvent match_state_event() const;
  bool counts() const { return phase_ == MatchPhase::Running; }
  void finish(wire::MatchEndReason reason);

  // Combat (match_combat.cpp).
  void fire_rifle(Player& shooter, const physics::Vec3& eye, const physics::Vec3& aim);
  void launch(Player& shooter, WeaponKind weapon, const physics::Vec3& eye,
              const physics::Vec3& aim);
  void explode(const Projectile& projectile, const physics::Vec3& center_m);
  /// Damage from `attacker` (null: it left the match) with `weapon`, after spawn protection,
  /// self damage and friendly fire. Returns the hit points taken.
  int hurt(Player& victim, Player* attacker, WeaponKind weapon, int damage);
  /// `from_world`: a kill volume or the map's bounds (no attacker, no weapon).
  void kill(Player& victim, Player* attacker, WeaponKind weapon, bool from_world);
  void clear_projectiles();
  void reset_pickups();

  // Recording (match_recording.cpp).
  void record_event(const RecordedEvent& event);

  MatchConfig config_;
  std::string map_name_;
  Map map_;
  physics::World world_;
  TickClock clock_;
  ProfileClock profile_clock_;
  MatchLog log_;
  std::uint32_t tick_ = 0;
  int snapshot_interval_ticks_ = 1;
  int ticks_since_snapshot_ = 0;
  std::uint32_t next_entity_id_ = 1;
  std::vector<Player> players_;          ///< sorted by entity id
  std::vector<PlayerScore> departed_;    ///< scores of players who left while running
  std::vector<Projectile> projectiles_;  ///< sorted by entity id
  std::vector<PickupState> pickups_;     ///< the map's, in order
  MatchPhase phase_ = MatchPhase::Waiting;
  std::uint32_t phase_started_tick_ = 0;
  std::uint32_t phase_ends_tick_ = 0;  ///< 0: open-ended
  std::array<int, 3> team_scores_{};
  wire::MatchEndReason end_reason_ = wire::MATCH_END_REASON_UNSPECIFIED;
  MatchRng rng_;
  LagCompensation lag_;
  std::vector<LagSample> lag_samples_;
  std::vector<ExplosionTarget> explosion_targets_;
  std::vector<ExplosionEffect> explosion_effects_;
  std::vector<std::uint32_t> explosion_entities_;  ///< entity of each explosion target
  std::vector<HistoryEntry> history_;              ///< ring by tick % history_ticks
  std::vector<physics::BodyId> body_ids_;          ///< scratch for World::read_bodies
  std::vector<physics::Vec3> positions_, velocities_;
  /// The payload receive() parses into, kept: parsing clears it but keeps its inputs'
  /// messages, so a payload allocates nothing.
  wire::ClientPayload incoming_;
  std::vector<proto::QuantizedEntity> quantized_;     ///< this snapshot's world
  proto::SnapshotEncodeCache snapshot_cache_;         ///< shared by the clients' encoders per tick
  std::vector<RecordedInput> step_inputs_;            ///< this step's, for the recording
  std::vector<RecordedEvent> pending_record_events_;  ///< since the last step
  std::unique_ptr<RecordingWriter> recording_;
  struct AddressedPayload {
    std::uint64_t account = 0;
    wire::ServerPayload payload;
  };
  std::vector<AddressedPayload> payloads_;  ///< built this tick, one per connected player
  std::size_t payload_count_ = 0;           ///< of payloads_ (kept for reuse), this tick's
  std::vector<Outgoing> pending_events_;    ///< reliable, sent in the next send phase
  std::vector<Outgoing> outbox_;
  std::size_t outbox_read_ = 0;
  TickProfile profile_;
  MatchCounters counters_;
};

}  // namespace ricochet::server
