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
#include "ricochet/proto/reliable_channel.h"
#include "ricochet/proto/snapshot_codec.h"
#include "ricochet/server/combat.h"
#include "ricochet/server/input_buffer.h"
#include "ricochet/server/live_frame.h"
#include "ricochet/server/map.h"
#include "ricochet/server/match_config.h"
#include "ricochet/server/recording.h"
#include "ricochet/server/rules.h"
#include "ricochet/server/tick_profile.h"
#include "ricochet/server/weapons.h"
#include "ricochet/wire/game.pb.h"

namespace ricochet::server {

// The bits of each entity's flags are proto/entity_flags.h's; what a chat line may hold is
// proto/chat_text.h's.
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
  TooLong,      ///< more than proto::kMaxChatBytes
  InvalidText,  ///< not UTF-8, or control or format characters (proto::check_chat_text)
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
  /// Of a reliable message: chat is Droppable (a player behind on its acks misses lines, never
  /// its connection), every other event MustArrive.
  proto::Delivery delivery = proto::Delivery::MustArrive;
};

/// A line for the server's log (rule violations, per player), from the match's thread.
using MatchLog = std::function<void(std::string_view line)>;

struct MatchParts;

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

  void set_log(MatchLog log);
  /// Publishes live frames to `feed` (live_frame.h) after each tick while it has viewers, at its
  /// rate of the server time tick() is given; nullptr stops. Changes no game state.
  void set_live_feed(std::shared_ptr<LiveFeed> feed);

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
  /// A chat line from the account, echoed to every connected player as a droppable event.
  /// Returns why it was refused, or nothing when it was accepted. Rate limits are the caller's.
  std::optional<ChatDrop> chat(std::uint64_t account, std::string_view text);

  /// Ends the match: every connected player gets a MatchEnded, put in the outbox at once (drain
  /// it before closing the connections); connect() refuses from now on. The match also ends by
  /// itself at its frag or time limit (rules.h).
  void end(wire::MatchEndReason reason);
  bool ended() const;
  wire::MatchEndReason end_reason() const;

  // --- the tick ---
  /// Runs the fixed steps due at `now`; after the last, builds and sends the snapshots when one
  /// is due. Returns the number of steps run. Drain the outbox after every call.
  int tick(proto::TimeUs now);
  /// Takes the next message to send, oldest first; false when the outbox is empty.
  bool poll_outbox(Outgoing& out);
  /// Messages poll_outbox still holds (to size the batch they go into).
  std::size_t outbox_size() const;
  /// When the next step is due: sleep until then.
  proto::TimeUs next_tick_at() const;

  // --- replay (recording.h) ---
  /// Plays back a membership change recorded before a step.
  void apply(const RecordedEvent& event);
  /// Runs one step with these inputs (players without one get the neutral input), as tick()
  /// would have with the inputs it applied; no snapshots are built.
  void step_recorded(std::span<const RecordedInput> inputs);
  /// The recording's bytes completed since the last take (RecordingWriter::take_completed):
  /// what the server appends to the file in progress. Empty when there are none or config.record
  /// is off.
  std::vector<std::uint8_t> take_recording_chunks();
  /// The rest of the recording, finished (footer written); empty when config.record is off. The
  /// match keeps no recording after this.
  std::vector<std::uint8_t> take_recording();
  /// The hash recordings check: the world's state_hash() and every game rule's state (health,
  /// armour, ammunition, scores, timers, pickups, projectiles, the generator).
  std::uint64_t state_hash() const;
  /// Tells `observer` every event the match broadcasts to its players (kills, joins, the match
  /// state...), once each as it is made, whether or not anyone is connected: a replay's kill
  /// feed. Called on the match's thread; empty: none.
  void observe_events(std::function<void(const wire::GameEvent&)> observer);

  // --- reading ---
  std::uint32_t id() const;
  const std::string& name() const;
  const std::string& map_name() const;
  const MatchConfig& config() const;
  std::uint32_t tick_number() const;
  MatchPhase phase() const;
  /// The tick the phase ends at (the warm-up's end, the time limit); 0: it has no end.
  std::uint32_t phase_ends_tick() const;
  int player_count() const;  ///< seated
  int connected_count() const;
  int max_players() const;
  std::optional<std::uint32_t> entity_of(std::uint64_t account) const;
  /// Every seated player, and everyone who left after taking part while the match was running
  /// (counts_in_record, match_record.h), by entity.
  std::vector<PlayerScore> scoreboard() const;
  /// Team scores by wire::Team (index 1 red, 2 blue; 0 unused), team deathmatch.
  std::array<int, 3> team_scores() const;
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
  const TickProfile& profile() const;
  const MatchCounters& counters() const;
  const physics::World& world() const;

 private:
  explicit Match(std::unique_ptr<MatchParts> parts);
  /// One step, the table of contents: every phase is deterministic.
  void simulate_step();

  std::unique_ptr<MatchParts> parts_;  ///< one allocation, at create() (src/match/match_parts.h)
};

}  // namespace ricochet::server
