#pragma once
/// The Recordings page's routes as requests and replies, socket-free (the admin port's wiring is
/// server_replays.cpp): the recordings directory listed (recording_catalog.h), replays started,
/// watched and cancelled on the replay pool (replay_jobs.h), their frames read by tick range
/// (replay_frames.h) and the top-down view of a recording's map (map_view.h).
///
///   GET  /api/recordings                             the list
///   GET  /api/recordings/<id>                        {"id","job":{...}|null,"summary":{...}|null}
///   GET  /api/recordings/<id>/frames?from=T0&to=T1   ticks [T0, T1) of a finished replay
///   GET  /api/recordings/<id>/map                    the recording's map, when the server has it
///   POST /api/recordings/<id>/replay                 starts (or reuses) its replay; busy: 503
///   POST /api/recordings/<id>/cancel                 stops it; 404 when none queued or running
///
/// Every id and query number from the URL is untrusted: checked before use and refused. A bad
/// id is 400 (counted by the catalog: bad_ids()); an unknown recording, an unknown path or
/// action, a missing or bad tick number and a tick range frames_json() refuses are 400 or 404
/// and counted in bad_requests(); a replay beyond dashboard.max_replays is 503 with the reason
/// (counted by the pool: refused_busy()). Frames before the replay is done are 409, a map the
/// server has not 404, a cancel with nothing to cancel 404: the page's own timing, not counted.

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>

#include "recording_catalog.h"
#include "replay_jobs.h"

namespace ricochet::server {

/// A request under /api/recordings as the routes see it.
struct RecordingsRequest {
  std::string_view method;  ///< "GET" or "POST"
  std::string_view path;    ///< the target less its query: "/api/recordings/<id>/frames"
  std::string_view query;   ///< after '?', undecoded; empty when none
};

/// An HTTP status and its body: JSON ("application/json") or a line for the operator.
struct RecordingsReply {
  unsigned status = 200;
  std::string body;
  std::string content_type = "text/plain; charset=utf-8";
};

/// The value of `key` in an undecoded query ("from=1&to=60") when it is there once, as 1..10
/// decimal digits that fit 32 bits; nothing otherwise (missing, empty, a sign or other
/// characters, 4294967296 and above, or the key given twice: which one was meant is unknown).
std::optional<std::uint32_t> query_tick(std::string_view query, std::string_view key);

/// What ReplayJobs replays from: the bytes of the recording `id` names in `catalog`'s directory,
/// or why not ("no recording <id>", "cannot read the recording").
ReplayJobs::Source recording_source(const RecordingCatalog& catalog);

class ReplayRoutes {
 public:
  /// Each map's top-down view JSON (map_view.h) by map name.
  using MapViews = std::map<std::string, std::string, std::less<>>;
  static constexpr std::string_view kListPath = "/api/recordings";
  static constexpr std::string_view kPrefix = "/api/recordings/";

  /// Keeps references: all three outlive it.
  ReplayRoutes(RecordingCatalog& catalog, ReplayJobs& jobs, const MapViews& map_views);

  /// Thread-safe. GET kListPath.
  RecordingsReply list();
  /// Thread-safe. A GET or POST under kPrefix.
  RecordingsReply answer(const RecordingsRequest& request);

  /// Requests refused as unknown (recording, path, action) or with bad tick numbers or ranges.
  std::uint64_t bad_requests() const { return bad_requests_.load(std::memory_order_relaxed); }

 private:
  RecordingsReply get(const std::string& id, std::string_view action, std::string_view query);
  RecordingsReply post(const std::string& id, std::string_view action);
  RecordingsReply refuse(unsigned status, std::string line);

  RecordingCatalog& catalog_;
  ReplayJobs& jobs_;
  const MapViews& map_views_;
  std::atomic<std::uint64_t> bad_requests_{0};
};

}  // namespace ricochet::server
