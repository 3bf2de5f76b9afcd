#pragma once
/// A recording re-simulated for the replay viewer: ricochet-replay's engine (replay.h over the
/// Match match_replay.h opens) run once, keeping after every step what a viewer draws, so it
/// can jump to any tick: every entity's position (the exact floats `ricochet-replay --export`
/// prints), the players' yaw, health and state, the projectiles, the kill feed and the score
/// changes from the replayed match's own events, and the hash verdict.
///
/// Socket-free and clock-free: a worker thread runs replay_frames() (replay_jobs.h), which
/// reports its progress and stops when asked through ReplayProgress.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <variant>
#include <vector>

#include "ricochet/server/recording.h"
#include "ricochet/server/replay.h"

namespace ricochet::server {

/// One entity after a step: 24 bytes.
struct FrameEntity {
  std::uint32_t id = 0;
  std::array<float, 3> position_m{};  ///< its centre, the simulation's float (no quantisation)
  float yaw_rad = 0;                  ///< a player's: the yaw of the input it last stepped with
  std::int16_t health = 0;            ///< a player's hit points; 0 for a projectile
  std::uint8_t flags = 0;             ///< proto/entity_flags.h: kind, dead, away, protected
};

struct FrameKill {
  std::uint32_t tick = 0;  ///< the step it happened in: the first frame showing it
  /// The tick the match's Kill event says (wire::Kill.tick, what clients saw): the step before
  /// for a shot fired in the step, which hits before the step's physics counts the tick.
  std::uint32_t event_tick = 0;
  std::uint32_t killer = 0;  ///< entity; 0: the world
  std::uint32_t victim = 0;
  std::uint8_t weapon = 0;  ///< a wire::Weapon; 0: the world
};

/// A player's score after step `tick`, kept when it differs from the step before.
struct FrameScore {
  std::uint32_t tick = 0;
  std::uint32_t entity = 0;
  std::int32_t kills = 0, deaths = 0, score = 0;
};

struct ReplayPlayer {
  std::uint64_t account = 0;
  std::string name;
  std::uint32_t entity = 0;  ///< the last entity it had
  std::uint8_t team = 0;     ///< a Team: 0 none, 1 red, 2 blue
};

struct ReplayFrames {
  std::uint32_t tick_rate_hz = 0;
  std::uint32_t last_tick = 0;  ///< ticks 1..last_tick are kept
  /// entities[tick_start[t - 1] .. tick_start[t]) are tick t's, by id.
  std::vector<std::uint32_t> tick_start{0};
  std::vector<FrameEntity> entities;
  std::vector<FrameKill> kills;       ///< by tick
  std::vector<FrameScore> scores;     ///< by tick, then entity
  std::vector<ReplayPlayer> players;  ///< everyone the scoreboard had at the end, by entity
  ReplayReport report;                ///< the hash verdict: first_mismatch, hashes_checked
  std::string cut;                    ///< the recording's `cut` when it is not complete

  /// What this holds in memory, bytes (the budget replay_jobs.h counts).
  std::size_t bytes() const;
};

/// Shared with the thread running replay_frames(): progress out, stop in.
struct ReplayProgress {
  std::atomic<std::uint32_t> ticks_done{0};
  std::uint32_t ticks_total = 0;  ///< the recording's last tick (set before the run)
  std::atomic<bool> stop{false};  ///< set from any thread: the run ends at its next step
  /// Set before the run, or empty: called on the replaying thread after each step, before
  /// `stop` is read (tests hold a replay there, mid-run).
  std::function<void(std::uint32_t tick)> after_step;
};

/// Re-simulates `recording`, keeping every step's frame. Fails with what was wrong: the map or
/// config refused ("its map: ..."), "stopped" (progress.stop), or the frames over `max_bytes`
/// ("the replay needs more than N bytes ..."). Steps stop at the first hash mismatch, as
/// ricochet-replay does without --keep-going.
std::variant<ReplayFrames, std::string> replay_frames(const Recording& recording,
                                                      ReplayProgress& progress,
                                                      std::size_t max_bytes);

/// At most this many ticks in one frames_json() document.
inline constexpr std::uint32_t kMaxFramesPerRequest = 600;

/// The frames of ticks [first, end) as JSON: every position printed as `ricochet-replay --export`
/// prints it (%.9g of the float), so the same text for the same tick and entity. Empty with
/// `error` set when the range is not within 1..last_tick + 1 or over kMaxFramesPerRequest ticks.
///   {"first_tick":T0,"end_tick":T1,"tick_rate_hz":60,
///    "scores":[{"entity":E,"kills":K,"deaths":D,"score":S}...]   (after step T0 - 1)
///    "frames":[{"tick":T,"players":[{"id","x","y","z","yaw","health","alive","away"}...],
///               "projectiles":[{"id","kind":"rocket"|"grenade","x","y","z"}...],
///               "kills":[{"killer","victim","weapon","tick"}...],   (in this step; "tick"
///                                                                the Kill event's own)
///               "scores":[...]}...]}                          (those that changed in it)
std::string frames_json(const ReplayFrames& frames, std::uint32_t first, std::uint32_t end,
                        std::string& error);

/// The replay's summary: {"last_tick","tick_rate_hz","seconds","complete","cut",
/// "hashes_checked","hashes_matched":bool,"first_mismatch_tick","players":[...],"kills":N}.
std::string replay_summary_json(const ReplayFrames& frames);

}  // namespace ricochet::server
