#pragma once
/// A live frame (live_frame.h) as the JSON a page reads, and a viewer's stream of them, encoded
/// on the viewer's thread, never on the match's.
///
/// The document (units: metres, m/s, radians, µs, seconds):
///   {"match": id, "tick": t, "server_time_us": µs, "tick_rate_hz": hz,
///    "phase": "waiting"|"warmup"|"running"|"ended", "time_left_s": s or null, "mode": "ffa"|"tdm",
///    "team_scores": {"red": n, "blue": n},
///    "players": [{"id", "name", "team": "red"|"blue"|null, "position": [x,y,z],
///                 "velocity": [x,y,z], "yaw", "health", "armor", "alive", "connected",
///                 "weapon": "rifle"|"rocket_launcher"|"grenade_launcher", "kills", "deaths",
///                 "score"}],
///    "projectiles": [{"id", "kind": "rocket"|"grenade", "owner", "position", "velocity"}],
///    "kills": [{"tick", "killer" (0: the world), "victim", "weapon": name or null}],
///    "kills_dropped": n}
/// A page draws 100 ms behind the newest frame, interpolating between the two frames around
/// that time by server_time_us (never extrapolating): frames come at the feed's rate, each after
/// a whole tick. Axes as map_view.h says.

#include <cstdint>
#include <optional>
#include <string>

#include "ricochet/server/live_frame.h"

namespace ricochet::server::web {

std::string frame_json(const LiveFrame& frame);

/// One viewer's frames: holds its seat on the feed and hands out each new frame once, encoded.
class FrameStream {
 public:
  explicit FrameStream(LiveFeed::Viewer viewer) : viewer_(std::move(viewer)) {}

  /// The newest frame as JSON when it is newer than the last one handed out; nullopt otherwise
  /// (none yet, or the same frame again): poll it at the feed's rate.
  std::optional<std::string> next();

 private:
  LiveFeed::Viewer viewer_;
  std::shared_ptr<const LiveFrame> last_;
};

}  // namespace ricochet::server::web
