#pragma once
/// The whole server process, wired: the DB worker, the matches (MatchRegistry, one MatchHost and
/// strand each), the UDP game channel, the TLS control channel and the admin HTTP port, all on
/// one io_context run by `server.threads` threads.
///
///   Server server(config);   // opens the DB and the map, makes the TLS pair; binds nothing
///   server.start();          // binds 7777/7778/9100, opens the matches, runs the threads
///   ...                      // SIGINT/SIGTERM (main) or a test calls stop()
///   int code = server.wait(); // 0 after a graceful stop within the grace period
///
/// A match that ends by itself (frag or time limit) is followed by the next of the rotation
/// (MatchRegistry); its record gets a uuid, is kept in the results outbox on local disk
/// (ResultsOutbox: it outlives the database being away and this process being killed) and goes
/// to the DB thread; each player gets its MatchResults over the control channel once it is
/// written, or at once with record_pending when the first write fails for a passing reason; its
/// recording goes to a file (RecordingFiles). At the start, the records an earlier process left
/// in the outbox are written (they have no one to tell).
///
/// Graceful stop, in order: refuse new joins; end every match and write the records of those
/// that had players to the DB (waiting for the writes), aborted; send each player its
/// MatchResults over the control channel; tell every game client (ServerShutdown) and close the
/// UDP socket; close the control channel (SHUTTING_DOWN to every client) and the admin port;
/// stop the threads; finish writing the recordings.

#include <array>
#include <atomic>
#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <variant>
#include <vector>

#include "episode_log.h"
#include "fleet_placement.h"
#include "overview.h"
#include "recording_catalog.h"
#include "replay_jobs.h"
#include "replay_routes.h"
#include "ricochet/db/fleet_records.h"
#include "ricochet/db/result.h"
#include "ricochet/server/config.h"
#include "ricochet/server/map.h"
#include "ricochet/server/metrics.h"

namespace ricochet::db {
class DbWorker;
struct DbServices;
}  // namespace ricochet::db
namespace ricochet::wire {
class MatchResults;
}

namespace ricochet::server {

class AdminHttp;
class AdminEventStream;
class AgonesHttp;
struct AccountAction;
struct AdminReply;
struct AdminRequest;
class ChatLimiter;
struct EndedMatch;
struct OutboxRecord;
class ControlServer;
class DirectoryHeartbeat;
class GameChannel;
class MatchHost;
class MatchRegistry;
class RecordingFiles;
class ResultsOutbox;

/// Why a live view request (/api/matches/<id>/map or /live) was refused.
enum class LiveRefusal {
  BadId,           ///< not a match id (web/match_id.h): 404
  UnknownMatch,    ///< no such match here (ended, or never): 404
  UnknownPath,     ///< neither /map nor /live after the id: 404
  TooManyViewers,  ///< the match's live_feed_max_viewers already watch: 503
};
inline constexpr std::size_t kLiveRefusalCount =
    static_cast<std::size_t>(LiveRefusal::TooManyViewers) + 1;
/// "bad_id", "unknown_match", "unknown_path", "too_many_viewers".
const char* name(LiveRefusal refusal);

class Server {
 public:
  /// A match's results (none when its record could not be written) and the accounts to tell.
  using ResultsHandler = std::function<void(std::optional<wire::MatchResults>,
                                            const std::vector<std::uint64_t>& recipients)>;

  /// Throws std::runtime_error with what went wrong (DB, map, TLS identity, config).
  explicit Server(ServerConfig config);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  /// Binds every socket, opens the configured matches and starts the threads; throws
  /// std::runtime_error naming the socket that could not be bound.
  void start();
  /// Starts the graceful stop on its own thread; thread-safe, idempotent.
  void stop();
  /// Blocks until stopped; the process's exit code (0: stopped within the grace period).
  int wait();

  std::uint16_t control_port() const;
  std::uint16_t game_port() const;
  std::uint16_t admin_port() const;
  const std::string& fingerprint() const;
  /// Sockets bound and the DB open.
  bool ready() const { return ready_.load(); }
  /// Every match ticked within the last second.
  bool healthy() const;
  MetricsRegistry& metrics() { return metrics_; }

 private:
  /// server.ports_file, when asked for: one JSON line, renamed into place; throws when it
  /// cannot be written.
  void write_ports_file() const;
  /// The graceful stop, on the stopping thread.
  void shut_down();
  void end_matches(std::chrono::steady_clock::time_point deadline);
  /// Any thread: the recording to its file, the record to the DB thread; `done` runs on the DB
  /// thread with the results and who gets them (nothing when the DB refused the record). A
  /// match nobody played in is not recorded: its results, with no players, go to whoever was
  /// seated (nothing when nobody was).
  void finish_match(EndedMatch match, ResultsHandler done);
  /// Submits the record; a write that failed for a passing reason (disk full, database
  /// locked or away) is kept and submitted again after kRecordRetryFirst, doubling up to
  /// kRecordRetryLast, until it is written or the server stops (its outbox file stays for the
  /// next start). `done` runs once: with the results once written, with them marked
  /// record_pending after a first write that failed for a passing reason, or with none when
  /// refused for good. The outbox file goes once written or refused for good; `from_outbox`:
  /// left by an earlier process, counted delivered once written.
  void write_record(std::shared_ptr<const EndedMatch> match, int attempt, ResultsHandler done,
                    bool from_outbox = false);
  /// At the start: every record an earlier process left in the outbox, to the database.
  void deliver_outbox();
  /// Every db.outbox_rescan_s while running: the records another process left in a shared outbox
  /// (ResultsOutbox::list_left), to the database.
  void rescan_outbox();
  /// `left` (from the outbox, not this process's matches) to the database.
  void deliver(std::vector<OutboxRecord> left);
  /// The results of a match whose record is not written yet: its players' kills, deaths, score
  /// and the rest they played, no rating or rank, record_pending set.
  static wire::MatchResults pending_results(const EndedMatch& match);
  /// The match's MatchResults over the control channel to each of `recipients`.
  void send_results(const wire::MatchResults& results,
                    const std::vector<std::uint64_t>& recipients);
  /// The results of `match` without its players: id, map, mode, how it ended, team scores.
  static wire::MatchResults results_header(const EndedMatch& match);
  /// On the DB thread: writes one ended match and reads back its players' ratings.
  static db::DbResult<wire::MatchResults> record(const EndedMatch& match, db::DbServices& services);
  void register_metrics();
  /// An operator's ban or unban (admin HTTP): the database first (a ban revokes the account's
  /// sessions), then, for a ban, the account's control sessions closed with ACCOUNT_BANNED and
  /// its game connection with reason banned, its seat given back. `answer` once, any thread.
  void act_on_account(AccountAction action, std::function<void(AdminReply)> answer);
  /// GET /fleet: the live directory through the DB worker (fleet_view.h), or 503.
  void answer_fleet(std::function<void(AdminReply)> answer);
  /// The Agones SDK client on the sidecar's `sdk_port` (AGONES_SDK_HTTP_PORT); throws
  /// std::runtime_error when it is not a port.
  void start_agones(const char* sdk_port);
  /// Every few seconds: the created matches empty for too long are closed.
  void sweep_empty_matches();
  /// The dashboard's routes on the admin port: GET /api/overview and /api/overview/events.
  void register_dashboard();
  /// The Recordings page's catalog and replay pool ([dashboard] replay_*).
  void start_replays();
  /// GET /api/recordings and the routes under /api/recordings/ (server_replays.cpp).
  void register_replays();
  void report_replays(MetricsSink& sink) const;
  /// Every kOverviewPeriod while running: the overview sampled (never on a match's strand)
  /// and sent to every stream of it.
  void sample_overview();
  /// What the overview shows now, read from the copies each part publishes (as /metrics).
  OverviewSample overview_sample() const;
  /// The live view's routes (server_live.cpp): GET /api/matches/<id>/map and the event stream
  /// GET /api/matches/<id>/live.
  void register_live();
  /// Counts and logs (once per episode) a refused live view request.
  void refuse_live(LiveRefusal refusal, std::string_view detail);
  /// Every live feed interval while running: each viewer's newest frame, encoded on an io_
  /// thread, pushed to its stream; viewers whose stream closed leave their seat.
  void poll_live();
  /// A /api/matches/ path's match (404 with the reason counted when there is none), or the
  /// refusal to answer with.
  std::variant<std::shared_ptr<MatchHost>, AdminReply> live_match(std::string_view id_text);
  /// [placement] on: the directory heartbeat, once the ports are bound (under Agones with an
  /// advertise key unset, once the sidecar said where players reach this server).
  void start_placement();
  /// Whether the directory row takes its address from Agones' GET /gameserver: under Agones,
  /// with placement on and an [placement] advertise key not set.
  bool advertises_from_agones() const;
  /// On an io_ thread: GET /gameserver's answer (`body`; nothing: refused) over the advertise
  /// keys not set, or, when it is not a GameServer's, the configured ones (logged, counted);
  /// then the heartbeats begin.
  void advertise_from_agones(const std::optional<std::string>& body);
  void start_heartbeats();

  static constexpr std::chrono::seconds kRecordRetryFirst{1};
  static constexpr std::chrono::seconds kRecordRetryLast{30};

  ServerConfig config_;
  boost::asio::io_context io_;
  MetricsRegistry metrics_;
  EpisodeLog episodes_;  ///< abuse refused on any channel, logged once per episode
  std::unique_ptr<ChatLimiter> chat_limiter_;
  PlacementCounters placement_counters_;
  /// [placement] on; the control sessions use it; declared before control_, so it outlives it.
  std::unique_ptr<FleetPlacement> placement_;
  std::unique_ptr<db::DbWorker> db_;
  std::unique_ptr<RecordingFiles> recordings_;
  std::unique_ptr<ResultsOutbox> outbox_;
  std::unique_ptr<RecordingCatalog> recording_catalog_;
  /// The replay workers; stopped (reset) once the io threads are joined.
  std::unique_ptr<ReplayJobs> replays_;
  /// The Recordings routes over the two above and map_views_; reset with replays_.
  std::unique_ptr<ReplayRoutes> replay_routes_;
  std::unique_ptr<GameChannel> game_;
  std::unique_ptr<MatchRegistry> matches_;
  std::unique_ptr<ControlServer> control_;
  std::unique_ptr<AdminHttp> admin_;
  /// Under Agones (AGONES_SDK_HTTP_PORT set); after matches_, whose stats it reads.
  std::unique_ptr<AgonesHttp> agones_;
  std::unique_ptr<DirectoryHeartbeat> heartbeat_;
  /// What the heartbeats write of this server; set before they begin, read on their strand.
  db::GameServerRow directory_row_;
  Counter* agones_game_server_invalid_ = nullptr;  ///< GET /gameserver answers not used
  boost::asio::steady_timer empty_match_sweep_{io_};
  boost::asio::steady_timer outbox_rescan_{io_};
  boost::asio::steady_timer overview_timer_{io_};
  Overview overview_;  ///< on overview_timer_'s handler only
  std::mutex overview_mutex_;
  std::string overview_json_;  ///< the last overview; guarded by overview_mutex_
  /// Open streams of the overview; guarded by overview_mutex_.
  std::vector<std::shared_ptr<AdminEventStream>> overview_streams_;
  /// Each map's top-down view (web/map_view.h) by map name, made once at the start.
  std::map<std::string, std::string, std::less<>> map_views_;
  boost::asio::steady_timer live_timer_{io_};
  struct LiveViewer;
  std::mutex live_mutex_;
  /// Open live streams with their seats; guarded by live_mutex_.
  std::vector<std::shared_ptr<LiveViewer>>
      live_viewers_;  ///< shared: LiveViewer is server_live.cpp's
  /// /api/matches/ requests refused, by LiveRefusal.
  std::array<std::atomic<std::uint64_t>, kLiveRefusalCount> live_refusals_{};
  std::vector<std::thread> threads_;
  std::thread stopper_;
  std::once_flag stop_once_;
  std::atomic<bool> ready_{false};
  std::atomic<int> exit_code_{0};
  std::atomic<bool> stopping_{false};
  std::atomic<std::uint64_t> records_pending_{0};   ///< kept after a failed write, to retry
  std::atomic<std::uint64_t> records_retried_{0};   ///< writes submitted again
  std::atomic<std::uint64_t> records_lost_{0};      ///< refused for good
  std::atomic<std::uint64_t> outbox_delivered_{0};  ///< left by an earlier process, now written
  std::atomic<std::uint64_t> bans_{0};              ///< accounts banned through admin HTTP
  std::atomic<std::uint64_t> unbans_{0};            ///< and unbanned
  std::atomic<std::uint64_t> banned_sessions_closed_{0};  ///< control sessions a ban closed
  std::atomic<std::uint64_t> banned_players_removed_{0};  ///< seats (and game connections) too
  std::mutex done_mutex_;
  std::condition_variable done_;
  bool stopped_ = false;
};

}  // namespace ricochet::server
