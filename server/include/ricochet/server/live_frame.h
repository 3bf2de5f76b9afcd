#pragma once
/// The live spectator feed of a match (issue 32, "A match, live"): what a top-down view draws at
/// one tick, and the hand-off that carries it from the match's thread to the viewers' threads.
///
/// The match builds a LiveFrame from what it already keeps after a step (its roster, its
/// projectiles, its rules), only while a viewer watches and at most once per
/// LiveFeedConfig::rate_hz of server time, and publishes it as an immutable shared copy: the tick
/// thread never encodes, never waits on a viewer and never changes game state for it (the state
/// hash and the snapshots are the same with and without viewers). Viewers read the newest frame
/// from any thread and encode it there (web/frame_json.h).
///
/// Coordinates are the physics world's: metres, +Y up, the ground plane is x-z; yaw is about +Y,
/// counter-clockwise seen from above, 0 facing -Z (combat.h aim_direction).

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "ricochet/proto/clock.h"
#include "ricochet/server/map.h"
#include "ricochet/server/rules.h"
#include "ricochet/server/weapons.h"

namespace ricochet::server {

/// One player as a frame shows it.
struct LivePlayer {
  std::uint32_t entity_id = 0;
  std::string name;
  Team team = Team::None;
  std::array<float, 3> position_m{};    ///< centre of its sphere (where it died while dead)
  std::array<float, 3> velocity_mps{};  ///< 0 while dead
  float yaw_rad = 0;                    ///< the aim the match accepted
  int health = 0;                       ///< 0..kMaxHealth
  int armor = 0;                        ///< 0..kMaxArmor
  bool alive = false;
  bool connected = false;  ///< false: within its reconnect grace, standing still
  WeaponKind weapon = WeaponKind::Rifle;
  int kills = 0;  ///< while running, as the scoreboard counts them
  int deaths = 0;
  int score = 0;
};

enum class LiveProjectileKind : std::uint8_t { Rocket, Grenade };
/// "rocket" or "grenade".
const char* name(LiveProjectileKind kind);

struct LiveProjectile {
  std::uint32_t entity_id = 0;
  LiveProjectileKind kind = LiveProjectileKind::Rocket;
  std::uint32_t owner_entity_id = 0;
  std::array<float, 3> position_m{};
  std::array<float, 3> velocity_mps{};
};

/// A death, as the clients' Kill event tells it.
struct LiveKill {
  std::uint32_t tick = 0;              ///< the step it happened in
  std::uint32_t killer_entity_id = 0;  ///< 0: the world (a kill volume, the bounds) or one who left
  std::uint32_t victim_entity_id = 0;
  /// The weapon; nullopt for the world.
  std::optional<WeaponKind> weapon;
};

/// What a viewer draws at one tick. Immutable once published.
struct LiveFrame {
  std::uint32_t match_id = 0;
  std::uint32_t tick = 0;            ///< steps run; one per 1 / tick_rate_hz s
  proto::TimeUs server_time_us = 0;  ///< the server's time (µs) handed to the tick that ran it
  int tick_rate_hz = 0;
  MatchPhase phase = MatchPhase::Waiting;
  /// Seconds until the phase ends (warmup, or the running match's time limit); nullopt when it
  /// is open-ended.
  std::optional<double> time_left_s;
  GameMode mode = GameMode::FreeForAll;
  std::array<int, 3> team_scores{};         ///< by Team (index 1 red, 2 blue; 0 unused)
  std::vector<LivePlayer> players;          ///< seated, by entity id
  std::vector<LiveProjectile> projectiles;  ///< in flight, by entity id
  /// Deaths since the previous frame published (the first frame: since the first viewer came),
  /// oldest first; at most kMaxLiveKills.
  std::vector<LiveKill> kills;
  /// Deaths that did not fit in `kills` (more than kMaxLiveKills between two frames).
  std::uint32_t kills_dropped = 0;
};

/// Deaths one frame carries; more between two frames are counted in kills_dropped.
inline constexpr std::size_t kMaxLiveKills = 64;

struct LiveFeedConfig {
  int rate_hz = 20;     ///< frames per second of server time, 1..60
  int max_viewers = 8;  ///< viewers watching one match at once, 1..64

  /// Empty when usable, else what is wrong ("rate_hz must be 1..60, got 0").
  std::string validate() const;
};

/// The hand-off of one match's frames: the match publishes on its thread, viewers read on
/// theirs. Create it with make_shared (viewers hold it); thread-safe.
class LiveFeed : public std::enable_shared_from_this<LiveFeed> {
 public:
  /// `config` must be valid (LiveFeedConfig::validate empty).
  explicit LiveFeed(const LiveFeedConfig& config);

  /// A viewer's seat: while one is held the match publishes. Move-only; leaving (destruction)
  /// frees the seat, and the last one leaving forgets the newest frame.
  class Viewer {
   public:
    Viewer(Viewer&& other) noexcept;
    Viewer& operator=(Viewer&& other) noexcept;
    Viewer(const Viewer&) = delete;
    Viewer& operator=(const Viewer&) = delete;
    ~Viewer();

    /// The newest frame, or nullptr before the first one since the first viewer came.
    std::shared_ptr<const LiveFrame> latest() const;

   private:
    friend class LiveFeed;
    explicit Viewer(std::shared_ptr<LiveFeed> feed) : feed_(std::move(feed)) {}
    std::shared_ptr<LiveFeed> feed_;
  };

  /// A seat, or nullopt when max_viewers are already watching.
  std::optional<Viewer> watch();
  /// Whether anyone watches: the match builds frames only then.
  bool watched() const { return viewers_.load(std::memory_order_acquire) > 0; }
  int viewers() const { return viewers_.load(std::memory_order_acquire); }
  /// Server time between two frames, µs.
  proto::TimeUs interval_us() const { return interval_us_; }

  /// The match's thread: replaces the newest frame (dropped when nobody watches any more).
  void publish(std::shared_ptr<const LiveFrame> frame);
  std::shared_ptr<const LiveFrame> latest() const;

 private:
  void leave();

  const proto::TimeUs interval_us_;
  const int max_viewers_;
  std::atomic<int> viewers_{0};
  mutable std::mutex mutex_;  ///< guards latest_ (a pointer swap on the tick thread)
  std::shared_ptr<const LiveFrame> latest_;
};

}  // namespace ricochet::server
