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
/// PlayerJoined for every player already there.

#include <array>
#include <cstdint>
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
#include "ricochet/server/input_buffer.h"
#include "ricochet/server/map.h"
#include "ricochet/server/movement.h"
#include "ricochet/server/tick_clock.h"
#include "ricochet/server/tick_profile.h"
#include "ricochet/wire/game.pb.h"

namespace ricochet::server {

/// Bits of proto::EntityState::flags as matches set them.
enum EntityFlag : std::uint8_t {
  kEntityGrounded = 1u << 0,      ///< standing on something
  kEntityDisconnected = 1u << 1,  ///< its player is away, within the reconnect grace
};

inline constexpr std::size_t kMaxChatBytes = 200;
inline constexpr std::size_t kMaxPlayerNameBytes = 32;
/// Largest ClientPayload accepted, bytes (a game datagram is at most 1200).
inline constexpr std::size_t kMaxClientPayloadBytes = 1200;

struct MatchConfig {
  std::uint32_t id = 1;
  std::string name = "match";
  int max_players = 16;                      ///< 1..64
  TickClockConfig tick;                      ///< rate 10..128 Hz (60), catch-up cap
  int snapshot_rate_hz = 60;                 ///< 1..tick.rate_hz: a snapshot every
                                             ///< round(tick / snapshot) ticks
  std::size_t snapshot_budget_bytes = 1100;  ///< serialised ServerPayload, 128..1100
  proto::TimeUs reconnect_grace_us = 30 * proto::kMicrosPerSecond;  ///< 0..300 s
  int history_ticks = 64;  ///< entity states kept for lag compensation, 1..1024
  MovementConfig movement;
  InputBufferConfig input;
  /// Quantisation of the snapshots; its bounds are replaced by the map's.
  proto::QuantizationSpec quantization;

  /// Empty when valid; otherwise names the field, the allowed range and what came.
  std::string validate() const;
};

/// Why connect() refused a player.
enum class JoinRefusal : std::uint8_t {
  MatchFull,    ///< max_players seated (connected or within their grace)
  InvalidName,  ///< not 1..32 bytes of printable UTF-8
};
inline constexpr std::size_t kJoinRefusalCount = 2;
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
inline constexpr std::size_t kChatDropCount = 4;
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
  /// A chat line from the account, echoed to every connected player. Returns why it was refused,
  /// or nothing when it was accepted.
  std::optional<ChatDrop> chat(std::uint64_t account, std::string_view text);

  // --- the tick ---
  /// Runs the fixed steps due at `now`; after the last, builds and sends the snapshots when one
  /// is due. Returns the number of steps run. Drain the outbox after every call.
  int tick(proto::TimeUs now);
  /// Takes the next message to send, oldest first; false when the outbox is empty.
  bool poll_outbox(Outgoing& out);
  /// When the next step is due: sleep until then.
  proto::TimeUs next_tick_at() const { return clock_.next_step_at(); }

  // --- reading ---
  std::uint32_t id() const { return config_.id; }
  const std::string& name() const { return config_.name; }
  const std::string& map_name() const { return map_name_; }
  const MatchConfig& config() const { return config_; }
  std::uint32_t tick_number() const { return tick_; }
  int player_count() const { return static_cast<int>(players_.size()); }  ///< seated
  int connected_count() const;
  int max_players() const { return config_.max_players; }
  std::optional<std::uint32_t> entity_of(std::uint64_t account) const;
  /// The entity states after the last step, sorted by id.
  std::span<const proto::EntityState> entity_states() const;
  /// The entity states after step `tick` while it is in the history ring (the last
  /// history_ticks steps), sorted by id; empty otherwise. For lag compensation.
  std::span<const proto::EntityState> states_at(std::uint32_t tick) const;
  const TickProfile& profile() const { return profile_; }
  const MatchCounters& counters() const { return counters_; }
  const physics::World& world() const { return world_; }

 private:
  struct Player {
    std::uint64_t account = 0;
    std::string name;
    std::uint32_t entity_id = 0;
    physics::BodyId body;
    bool connected = true;
    proto::TimeUs disconnected_at = 0;
    bool grounded = false;
    InputBuffer inputs;
    PlayerInput applied;                                ///< this step's input
    std::unique_ptr<proto::SnapshotEncoder> snapshots;  ///< per connection, none while away
  };
  struct HistoryEntry {
    std::uint32_t tick = 0;
    std::vector<proto::EntityState> states;  ///< sorted by id
  };

  Match(const MatchConfig& config, physics::World world, const Map& map, proto::TimeUs now,
        ProfileClock profile_clock);

  // The phases of a step and of a snapshot (match_phases.cpp).
  void apply_inputs();
  void move_players();
  void step_physics();
  void record_history();
  void build_snapshots();
  void send();

  /// Runs one phase, adding its time to `ms`.
  void run_phase(void (Match::*phase)(), double& ms);
  Player* find(std::uint64_t account);
  const Player* find(std::uint64_t account) const;
  physics::Vec3 choose_spawn();
  void remove_player(std::size_t index, wire::LeaveReason reason);
  void expire_disconnected(proto::TimeUs now);
  void broadcast(const wire::GameEvent& event);
  void queue_event(std::uint64_t account, const wire::GameEvent& event);
  /// Forgets the events queued for `account`: its connection is gone or replaced.
  void drop_pending_events(std::uint64_t account);
  /// Tells `account` that `other` is in the match (a PlayerJoined).
  void queue_present(std::uint64_t account, const Player& other);
  double elapsed_ms(std::int64_t since_ns) const;
  std::int64_t profile_now() const;

  MatchConfig config_;
  std::string map_name_;
  std::vector<physics::Vec3> spawns_;
  physics::Real bounds_max_y_m_ = 0;  ///< highest spawn centre that keeps a player inside
  std::size_t next_spawn_ = 0;
  physics::World world_;
  TickClock clock_;
  ProfileClock profile_clock_;
  std::uint32_t tick_ = 0;
  int snapshot_interval_ticks_ = 1;
  int ticks_since_snapshot_ = 0;
  std::uint32_t next_entity_id_ = 1;
  std::vector<Player> players_;            ///< sorted by entity id
  std::vector<HistoryEntry> history_;      ///< ring by tick % history_ticks
  std::vector<physics::BodyId> body_ids_;  ///< scratch for World::read_bodies
  std::vector<physics::Vec3> positions_, velocities_;
  std::vector<proto::QuantizedEntity> quantized_;  ///< this snapshot's world
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
