// What /metrics reports about the running server, read at scrape time from the copies each
// part publishes (the game channel after every update, each match after every tick, the control
// channel's atomic counters, the DB worker's queue), so a scrape never touches game state.
#include <sys/resource.h>
#include <unistd.h>

#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include "chat_limiter.h"
#include "control_server.h"
#include "fleet_placement.h"
#include "game_channel.h"
#include "match_registry.h"
#include "recording_files.h"
#include "results_outbox.h"
#include "ricochet/db/db_worker.h"
#include "server.h"

namespace ricochet::server {

namespace {

void report_game_channel(const proto::TransportCounters& game, MetricsSink& sink) {
  sink.counter("ricochet_game_packets_total", "Game channel datagrams", {{"direction", "in"}},
               static_cast<double>(game.packets_in));
  sink.counter("ricochet_game_packets_total", "Game channel datagrams", {{"direction", "out"}},
               static_cast<double>(game.packets_out));
  sink.counter("ricochet_game_bytes_total", "Game channel bytes", {{"direction", "in"}},
               static_cast<double>(game.bytes_in));
  sink.counter("ricochet_game_bytes_total", "Game channel bytes", {{"direction", "out"}},
               static_cast<double>(game.bytes_out));
  for (std::size_t i = 0; i < proto::kDropReasonCount; ++i) {
    sink.counter("ricochet_game_dropped_total", "Game channel datagrams dropped, by reason",
                 {{"reason", std::string(proto::name(static_cast<proto::DropReason>(i)))}},
                 static_cast<double>(game.drops[i]));
  }
  for (std::size_t i = 0; i < proto::kDisconnectReasonCount; ++i) {
    sink.counter("ricochet_game_disconnects_total", "Game connections ended, by reason",
                 {{"reason", std::string(proto::name(static_cast<proto::DisconnectReason>(i)))}},
                 static_cast<double>(game.disconnects[i]));
  }
  sink.counter("ricochet_game_handshakes_total", "Game channel handshakes completed", {},
               static_cast<double>(game.connections_total));
  sink.counter("ricochet_game_reliable_resends_total",
               "Reliable messages sent again for want of an ack", {},
               static_cast<double>(game.reliable_resends));
  sink.counter("ricochet_game_reliable_dropped_total",
               "Droppable reliable messages (chat) not queued: the client was behind on its acks",
               {}, static_cast<double>(game.reliable_dropped));
  sink.gauge("ricochet_game_connections", "Game connections by state", {{"state", "half_open"}},
             game.half_open);
  sink.gauge("ricochet_game_connections", "Game connections by state", {{"state", "connected"}},
             game.connected);
}

void report_control_channel(const ControlStats& control, MetricsSink& sink) {
  sink.counter("ricochet_control_accepted_total", "TCP connections accepted on the control port",
               {}, static_cast<double>(control.accepted));
  sink.gauge("ricochet_control_connections", "Control connections by state",
             {{"state", "tls_handshake"}}, static_cast<double>(control.handshaking));
  for (std::size_t i = 0; i < proto::kControlStateCount; ++i) {
    sink.gauge("ricochet_control_connections", "Control connections by state",
               {{"state", proto::name(static_cast<proto::ControlState>(i))}},
               static_cast<double>(control.by_state[i]));
  }
  sink.counter("ricochet_control_frames_total", "Control frames", {{"direction", "in"}},
               static_cast<double>(control.frames_in));
  sink.counter("ricochet_control_frames_total", "Control frames", {{"direction", "out"}},
               static_cast<double>(control.frames_out));
  sink.counter("ricochet_control_bytes_total", "Control channel plaintext bytes",
               {{"direction", "in"}}, static_cast<double>(control.bytes_in));
  sink.counter("ricochet_control_bytes_total", "Control channel plaintext bytes",
               {{"direction", "out"}}, static_cast<double>(control.bytes_out));
  for (std::size_t i = 0; i < proto::kClientMessageKindCount; ++i) {
    sink.counter("ricochet_control_requests_total", "Control requests dispatched, by kind",
                 {{"kind", proto::name(static_cast<proto::ClientMessageKind>(i))}},
                 static_cast<double>(control.requests[i]));
  }
  for (std::size_t i = 0; i < kControlRefusalCount; ++i) {
    sink.counter("ricochet_control_refused_total",
                 "Control connections, frames and messages refused, by reason",
                 {{"reason", name(static_cast<ControlRefusal>(i))}},
                 static_cast<double>(control.refusals[i]));
  }
}

void report_match(const MatchHost& host, MetricsSink& sink) {
  const MatchHostStats stats = host.stats();
  const MetricLabels match = {{"match", std::to_string(host.id())}};
  const auto with = [&match](const char* key, std::string value) {
    MetricLabels labels = match;
    labels.emplace_back(key, std::move(value));
    return labels;
  };
  sink.gauge("ricochet_match_players",
             "Players per match: seated (connected or within the "
             "reconnect grace) and connected",
             with("state", "seated"), stats.seated);
  sink.gauge("ricochet_match_players",
             "Players per match: seated (connected or within the "
             "reconnect grace) and connected",
             with("state", "connected"), stats.connected);
  const MatchCounters& counters = stats.counters;
  sink.counter("ricochet_match_steps_total", "Fixed steps run", match,
               static_cast<double>(counters.steps));
  sink.counter("ricochet_match_overruns_total", "Ticks that hit the catch-up cap", match,
               static_cast<double>(counters.overruns));
  sink.counter("ricochet_match_dropped_steps_total", "Fixed steps skipped after a stall", match,
               static_cast<double>(counters.dropped_steps));
  sink.counter("ricochet_match_snapshots_total", "Snapshots sent", match,
               static_cast<double>(counters.snapshots_sent));
  sink.counter("ricochet_match_snapshot_bytes_total", "Serialised ServerPayload bytes", match,
               static_cast<double>(counters.snapshot_bytes));
  sink.counter("ricochet_match_inputs_total", "Player steps with a fresh or a repeated input",
               with("kind", "applied"), static_cast<double>(counters.inputs_applied));
  sink.counter("ricochet_match_inputs_total", "Player steps with a fresh or a repeated input",
               with("kind", "repeated"), static_cast<double>(counters.inputs_repeated));
  for (std::size_t i = 0; i < kInputDropCount; ++i) {
    sink.counter("ricochet_match_input_dropped_total",
                 "Client payloads or inputs dropped, by reason",
                 with("reason", name(static_cast<InputDrop>(i))),
                 static_cast<double>(counters.input_drops[i]));
  }
  for (std::size_t i = 0; i < kChatDropCount; ++i) {
    sink.counter("ricochet_match_chat_dropped_total", "Chat lines dropped, by reason",
                 with("reason", name(static_cast<ChatDrop>(i))),
                 static_cast<double>(counters.chat_drops[i]));
  }
  for (std::size_t i = 0; i < kJoinRefusalCount; ++i) {
    sink.counter("ricochet_match_join_refused_total", "Players refused entry, by reason",
                 with("reason", name(static_cast<JoinRefusal>(i))),
                 static_cast<double>(counters.join_refusals[i]));
  }
}

/// Seconds since the Unix epoch at which this process started: its start in clock ticks after
/// boot (/proc/self/stat, field 22) plus the boot time (/proc/stat, btime). nullopt when either
/// cannot be read.
std::optional<double> process_start_time_s() {
  std::ifstream stat_file("/proc/self/stat");
  std::string stat;
  std::getline(stat_file, stat);
  // Field 2, the command name, is in parentheses and may hold spaces and ')': the fields after
  // it start after the last ')', at field 3.
  const auto name_end = stat.rfind(')');
  if (name_end == std::string::npos) return std::nullopt;
  std::istringstream fields(stat.substr(name_end + 1));
  std::string skipped;
  for (int field = 3; field < 22; ++field) fields >> skipped;
  std::uint64_t start_ticks = 0;
  if (!(fields >> start_ticks)) return std::nullopt;
  std::ifstream system_stat("/proc/stat");
  std::string line;
  while (std::getline(system_stat, line)) {
    std::uint64_t boot_s = 0;
    if (std::sscanf(line.c_str(), "btime %" SCNu64, &boot_s) == 1) {
      return static_cast<double>(boot_s) +
             static_cast<double>(start_ticks) / static_cast<double>(sysconf(_SC_CLK_TCK));
    }
  }
  return std::nullopt;
}

/// Prometheus' standard process metrics (the names and types of its client libraries), read at
/// scrape time: what a soak run watches for leaks, and what a load test reads of a server whose
/// /proc it cannot see. Then the database's size on disk.
void report_process(const std::string& db_file, MetricsSink& sink) {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) == 0) {
    const auto seconds = [](const timeval& time) {
      return static_cast<double>(time.tv_sec) + static_cast<double>(time.tv_usec) / 1e6;
    };
    sink.counter("process_cpu_seconds_total", "Total user and system CPU time spent in seconds", {},
                 seconds(usage.ru_utime) + seconds(usage.ru_stime));
  }
  std::ifstream statm("/proc/self/statm");
  std::uint64_t pages = 0;
  std::uint64_t resident = 0;
  if (statm >> pages >> resident) {
    const auto page_bytes = static_cast<std::uint64_t>(sysconf(_SC_PAGESIZE));
    sink.gauge("process_resident_memory_bytes", "Resident memory size in bytes", {},
               static_cast<double>(resident * page_bytes));
    sink.gauge("process_virtual_memory_bytes", "Virtual memory size in bytes", {},
               static_cast<double>(pages * page_bytes));
  }
  std::error_code error;
  std::size_t fds = 0;
  for (std::filesystem::directory_iterator it("/proc/self/fd", error), end; !error && it != end;
       it.increment(error)) {
    ++fds;
  }
  if (!error) {
    sink.gauge("process_open_fds", "Number of open file descriptors", {},
               static_cast<double>(fds > 0 ? fds - 1 : 0));  // less the one listing them
  }
  rlimit fd_limit{};
  if (getrlimit(RLIMIT_NOFILE, &fd_limit) == 0 && fd_limit.rlim_cur != RLIM_INFINITY) {
    sink.gauge("process_max_fds", "Maximum number of open file descriptors", {},
               static_cast<double>(fd_limit.rlim_cur));
  }
  if (const auto start_s = process_start_time_s()) {
    sink.gauge("process_start_time_seconds",
               "Start time of the process since unix epoch in seconds", {}, *start_s);
  }
  std::uint64_t bytes = 0;
  for (const char* suffix : {"", "-wal"}) {
    const auto size = std::filesystem::file_size(db_file + suffix, error);
    if (!error) bytes += size;
  }
  sink.gauge("ricochet_db_file_bytes", "Size of the database file and its write-ahead log", {},
             static_cast<double>(bytes));
}

}  // namespace

void Server::register_metrics() {
  metrics_.add_collect_callback([this](MetricsSink& sink) {
    report_game_channel(game_->counters(), sink);
    report_control_channel(control_->stats(), sink);
    for (std::size_t i = 0; i < kTicketResultCount; ++i) {
      sink.counter("ricochet_placement_tickets_total",
                   "find_match requests answered here, by result: assigned (a ticket issued) or "
                   "why not",
                   {{"result", name(static_cast<TicketResult>(i))}},
                   static_cast<double>(placement_counters_.tickets[i].load()));
    }
    for (std::size_t i = 0; i < kHeartbeatOutcomeCount; ++i) {
      sink.counter("ricochet_placement_heartbeats_total",
                   "Writes of this server's fleet directory row, by outcome",
                   {{"outcome", name(static_cast<HeartbeatOutcome>(i))}},
                   static_cast<double>(placement_counters_.heartbeats[i].load()));
    }
    for (std::size_t i = 0; i < kLiveRefusalCount; ++i) {
      sink.counter("ricochet_live_view_refused_total",
                   "Requests of a match's live view (/api/matches/<id>/map or /live) refused, by "
                   "reason",
                   {{"reason", name(static_cast<LiveRefusal>(i))}},
                   static_cast<double>(live_refusals_[i].load()));
    }
    const auto hosts = matches_->hosts();
    sink.gauge("ricochet_matches", "Matches hosted", {}, static_cast<double>(hosts.size()));
    sink.gauge("ricochet_players",
               "Players seated in any match (connected, within the reconnect "
               "grace, or holding a fresh connect token)",
               {}, static_cast<double>(matches_->seats()));
    sink.counter("ricochet_game_unexpected_reliable_total",
                 "Reliable messages from clients, none being defined (dropped)", {},
                 static_cast<double>(matches_->unexpected_reliable()));
    const auto chat_refusals = chat_limiter_->refusals();
    for (std::size_t i = 0; i < kChatLimitCount; ++i) {
      sink.counter("ricochet_chat_refused_total",
                   "Chat lines refused with RATE_LIMITED, by the limit they broke",
                   {{"limit", name(static_cast<ChatLimit>(i))}},
                   static_cast<double>(chat_refusals[i]));
    }
    for (std::size_t i = 0; i < kSeatRefusalCount; ++i) {
      const auto refusal = static_cast<SeatRefusal>(i);
      sink.counter("ricochet_match_limit_refused_total",
                   "Joins and match creations refused by a seat or creation limit, by reason",
                   {{"reason", name(refusal)}}, static_cast<double>(matches_->refused(refusal)));
    }
    sink.counter("ricochet_matches_closed_empty_total",
                 "Created matches closed after staying empty too long", {},
                 static_cast<double>(matches_->empty_matches_closed()));
    for (const auto& host : hosts) {
      report_match(*host, sink);
      host->report_phases(sink);
    }
    sink.counter("ricochet_recordings_total", "Match recordings written to disk, or not",
                 {{"result", "written"}}, static_cast<double>(recordings_->written()));
    sink.counter("ricochet_recordings_total", "Match recordings written to disk, or not",
                 {{"result", "failed"}}, static_cast<double>(recordings_->failed()));
    sink.counter("ricochet_recording_bytes_total", "Bytes of the match recordings written", {},
                 static_cast<double>(recordings_->written_bytes()));
    report_replays(sink);
    sink.gauge("ricochet_match_records_pending",
               "Ended matches whose record could not be written yet (disk full, database "
               "locked): kept and written again",
               {}, static_cast<double>(records_pending_.load()));
    sink.counter("ricochet_match_record_retries_total", "Match records submitted again", {},
                 static_cast<double>(records_retried_.load()));
    sink.counter("ricochet_match_records_lost_total",
                 "Match records the database refused for good (invalid; logged)", {},
                 static_cast<double>(records_lost_.load()));
    sink.gauge("ricochet_results_outbox_files",
               "Ended matches' records kept on local disk until the database has them", {},
               static_cast<double>(outbox_->files()));
    sink.counter("ricochet_results_outbox_delivered_total",
                 "Records left in the outbox by an earlier process, written since the start", {},
                 static_cast<double>(outbox_delivered_.load()));
    sink.counter("ricochet_results_outbox_rejected_total",
                 "Outbox files that were not a match record (corrupt, truncated, oversized), "
                 "moved to its rejected/ directory",
                 {}, static_cast<double>(outbox_->rejected()));
    for (const auto& [action, count] :
         {std::pair{"ban", bans_.load()}, std::pair{"unban", unbans_.load()}}) {
      sink.counter("ricochet_account_bans_total",
                   "Accounts banned or unbanned by an operator (admin HTTP), by action",
                   {{"action", action}}, static_cast<double>(count));
    }
    for (const auto& [what, count] : {std::pair{"control_sessions", banned_sessions_closed_.load()},
                                      std::pair{"players", banned_players_removed_.load()}}) {
      sink.counter("ricochet_ban_closed_total",
                   "What bans closed: control connections signed in as the banned account, and "
                   "players taken out of their match (seat and game connection)",
                   {{"what", what}}, static_cast<double>(count));
    }
    sink.gauge("ricochet_db_queue_depth", "Jobs waiting for the DB thread", {},
               static_cast<double>(db_->queued()));
    sink.gauge("ricochet_up", "1 while the server is ready", {}, ready() ? 1 : 0);
    report_process(config_.db_file(), sink);
    sink.gauge("ricochet_process_id",
               "The server's process id (a load test on this host reads its CPU and RSS in /proc)",
               {}, static_cast<double>(getpid()));
  });
}

}  // namespace ricochet::server
