#pragma once
/// What the server tells Agones, and when: a sans-IO state machine (no sockets, no clock). Events
/// and the time (steady µs) come in; the HTTP calls to make go out, one at a time, to the SDK
/// sidecar's REST gateway on localhost:${AGONES_SDK_HTTP_PORT}. The I/O is AgonesHttp's
/// (agones_http.h).
///
/// The gateway's contract (Agones' sdks/swagger/sdk.swagger.json; every body JSON,
/// Content-Type application/json; every answer 200 with `{}`):
///
///   POST /ready           {}                             the server takes players
///   POST /health          {}                             a ping; health.periodSeconds apart
///   POST /allocate        {}                             the GameServer is Allocated
///   POST /shutdown        {}                             the GameServer is shut down (pod deleted)
///   PUT  /metadata/label  {"key":"map","value":"arena"}  label agones.dev/sdk-map=arena
///   GET  /gameserver      (no body)                      the GameServer (agones_game_server.h)
///
/// The rules:
///   - POST /ready once, after ready() (sockets bound, the database open);
///   - GET /gameserver once after /ready was answered, when fetch_game_server() asked for it
///     (where players reach this server, for the fleet directory); its answer, or the refusal
///     of it, is taken with take_game_server();
///   - POST /health every health_interval_us from then on, while every match ticks on time: each
///     ticked within stuck_after_us and none overran its catch-up cap since the previous ping. A
///     stuck or overrunning match withholds pings (counted, logged once per episode), so after
///     failureThreshold missed pings of periodSeconds the sidecar marks the GameServer
///     Unhealthy and Agones replaces it. While stopping, pings go on whatever the matches do
///     (they are being ended on purpose);
///   - PUT /metadata/label for map, mode, players and capacity when their value changes, each
///     key at most once per label_interval_us (the latest value goes);
///   - POST /allocate once: at the first player the fleet placed here (players_placed(): a
///     join_match with a ticket, before its game connection), or at the first player seated
///     (observe(): a direct join, once its game connection is up). Allocated protects the
///     GameServer from a scale-down, which deletes Ready ones: a direct join on a lone server, or
///     on a Ready server of a fleet (a client that listed its matches), has players on it as
///     much as a placed one. It waits for the seat, not the join, because the allocation is
///     never undone here: a join that never connects (an account needs only a TLS connection
///     for it) must not take a GameServer out of the Ready buffer for good. A placed join is
///     trusted at once: the ticket was rate-limited by find_match and claimed in the database;
///     (OPERATIONS.md, Agones);
///   - POST /shutdown once, after drained() (the graceful stop is done) or when
///     shutdown_after_matches matches have finished (Agones then deletes the pod, whose SIGTERM
///     drains the server); nothing is sent after it is answered.
/// A call that finds no sidecar (connection refused: it may still be starting), times out or is
/// answered 5xx stays pending and is retried after a back-off (retry_first_us doubling up to
/// retry_last_us); a 4xx answer drops the call (our request is wrong: retrying cannot help).
/// Each outcome is counted; a failing episode is logged once when it starts and once when the
/// sidecar answers again.

#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "ricochet/proto/clock.h"

namespace ricochet::server {

enum class AgonesCall : std::uint8_t { Ready, Health, Label, Allocate, Shutdown, GameServer };
inline constexpr std::size_t kAgonesCallCount =
    static_cast<std::size_t>(AgonesCall::GameServer) + 1;
/// "ready", "health", "label", "allocate", "shutdown", "gameserver"
const char* name(AgonesCall call);

enum class AgonesOutcome : std::uint8_t {
  Ok,           ///< 2xx
  IoError,      ///< no connection (refused, reset) or no HTTP answer
  Timeout,      ///< no answer within the call's time limit
  ServerError,  ///< 5xx
  ClientError,  ///< 4xx, or another status: the request is wrong; dropped
};
inline constexpr std::size_t kAgonesOutcomeCount =
    static_cast<std::size_t>(AgonesOutcome::ClientError) + 1;
/// "ok", "io_error", "timeout", "http_5xx", "http_4xx"
const char* name(AgonesOutcome outcome);

/// One HTTP call to the sidecar.
struct AgonesRequest {
  AgonesCall call = AgonesCall::Ready;
  std::string method;  ///< "POST", "PUT" or "GET"
  std::string path;    ///< "/ready", "/metadata/label", ...
  std::string body;    ///< JSON: "{}" or {"key":"...","value":"..."}; empty for a GET
};

/// How GET /gameserver settled.
struct AgonesGameServerAnswer {
  std::optional<std::string> body;  ///< the 2xx answer's body; nothing: refused (4xx)
};

/// One match as the SDK sees it, read from its host's published stats.
struct AgonesMatchView {
  std::uint32_t id = 0;
  std::string map;                 ///< the map's name
  std::string mode;                ///< "ffa", "tdm"
  int players = 0;                 ///< seated
  int capacity = 0;                ///< max players
  proto::TimeUs last_tick_at = 0;  ///< steady µs of its last tick
  std::uint64_t overruns = 0;      ///< ticks that hit the catch-up cap, since it opened
};

struct AgonesSdkConfig {
  /// Agones' fleet must allow for it: health.periodSeconds at least this, failureThreshold
  /// missed pings before Unhealthy.
  proto::TimeUs health_interval_us = 2 * proto::kMicrosPerSecond;
  /// A match whose last tick is older than this is stuck (it ticks 10-128 times a second).
  proto::TimeUs stuck_after_us = proto::kMicrosPerSecond;
  /// At most one PUT of a label key per this long.
  proto::TimeUs label_interval_us = proto::kMicrosPerSecond;
  proto::TimeUs retry_first_us = 250 * proto::kMicrosPerMilli;
  proto::TimeUs retry_last_us = 2 * proto::kMicrosPerSecond;
  /// agones.shutdown_after_matches: matches finished before POST /shutdown; 0: never.
  int shutdown_after_matches = 0;
};

struct AgonesCounters {
  /// By call and outcome.
  std::array<std::array<std::uint64_t, kAgonesOutcomeCount>, kAgonesCallCount> calls{};
  std::uint64_t health_withheld = 0;  ///< pings not sent: a match was stuck or overran
  std::uint64_t matches_finished = 0;
};

class AgonesSdk {
 public:
  explicit AgonesSdk(AgonesSdkConfig config = {});

  // Events.
  /// Sockets bound and the database open: POST /ready, then the pings begin.
  void ready(proto::TimeUs now);
  /// The matches now; labels follow their changes, pings their ticks, and the first seated
  /// player (a direct join's) allocates as players_placed() does.
  void observe(std::vector<AgonesMatchView> matches);
  /// A ticket seated its player here: POST /allocate (once; not while stopping), so that a
  /// scale-down never picks this GameServer while players are on it.
  void players_placed();
  /// GET /gameserver once the GameServer is Ready (once; not while stopping).
  void fetch_game_server();
  /// A match ended by itself (frag or time limit).
  void match_finished();
  /// The graceful stop began: no more labels or allocation; pings go on.
  void stopping();
  /// The graceful stop is done: POST /shutdown.
  void drained();

  /// The call to make now, if any (none while one is in flight, during a back-off, or after the
  /// shutdown was answered). Answer it with call_done().
  std::optional<AgonesRequest> next_call(proto::TimeUs now);
  /// How the call from next_call() went; `body`: the answer's (kept for GET /gameserver).
  void call_done(AgonesOutcome outcome, proto::TimeUs now, std::string_view body = {});
  /// GET /gameserver's answer once it settled (once), else nothing.
  std::optional<AgonesGameServerAnswer> take_game_server();
  /// When next_call() may have something without a new event (a ping or a label due, a
  /// back-off ending); nullopt: only an event can bring a call.
  std::optional<proto::TimeUs> next_due(proto::TimeUs now) const;

  /// POST /shutdown was answered (or refused for good): nothing more will be sent.
  bool finished() const { return shutdown_done_; }
  bool is_ready() const { return ready_done_; }
  const AgonesCounters& counters() const { return counters_; }

  /// The label keys, as PUT (the sidecar prefixes them with "agones.dev/sdk-").
  static constexpr std::array<std::string_view, 4> kLabelKeys = {"map", "mode", "players",
                                                                 "capacity"};
  /// `text` as a Kubernetes label value: at most 63 of [A-Za-z0-9._-], beginning and ending
  /// with a letter or digit; other characters become '-'.
  static std::string label_value(std::string_view text);

 private:
  struct Label {
    std::string wanted;  ///< the value the matches have now
    std::optional<std::string> sent;
    proto::TimeUs sent_at = 0;
  };
  /// Whether a ping may go now; counts and logs a withheld one.
  bool ticking_on_time(proto::TimeUs now);
  std::optional<AgonesRequest> due_label(proto::TimeUs now);
  AgonesRequest post(AgonesCall call) const;
  /// The call in flight is done with: answered 2xx (`accepted`, with `body`) or refused with a
  /// 4xx.
  void settled(proto::TimeUs now, bool accepted, std::string_view body);
  /// GET /gameserver is due (asked for, Ready answered, not yet settled).
  bool game_server_due() const;

  AgonesSdkConfig config_;
  bool ready_requested_ = false;
  bool ready_done_ = false;
  bool allocate_requested_ = false;
  bool allocate_done_ = false;
  bool shutdown_requested_ = false;
  bool shutdown_done_ = false;
  bool stopping_ = false;
  bool game_server_requested_ = false;
  bool game_server_done_ = false;
  std::optional<AgonesGameServerAnswer> game_server_answer_;  ///< until taken
  proto::TimeUs health_due_at_ = 0;
  std::vector<AgonesMatchView> matches_;
  std::map<std::uint32_t, std::uint64_t> overruns_at_last_ping_;  ///< by match id
  bool withholding_ = false;  ///< in an episode of withheld pings
  std::map<std::string, Label, std::less<>> labels_;
  std::optional<AgonesRequest> in_flight_;
  proto::TimeUs in_flight_since_ = 0;
  std::pair<std::string, std::string> in_flight_label_;  ///< key and value a Label call sets
  proto::TimeUs retry_at_ = 0;
  proto::TimeUs backoff_us_ = 0;
  std::uint64_t failures_in_episode_ = 0;
  proto::TimeUs episode_started_at_ = 0;
  AgonesCounters counters_;
};

}  // namespace ricochet::server
