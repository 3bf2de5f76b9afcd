#pragma once
/// This server's row in the fleet directory (db::Placement), kept by heartbeats: on a timer
/// whose timing is HeartbeatSchedule's, the row and the matches `describe` gives are written
/// through the DB worker, stale servers and expired tickets purged, and the seats open tickets
/// hold here handed to the match registry (they count against direct joins). leave() at
/// shutdown deletes the row, so nobody is placed here any more.
///
///   start() ─▶ [timer at next_at] ─▶ DB thread: heartbeat, purge_stale, held_seats
///                     ▲                                  │
///                     └──── finished(written), next ◀────┘ (on this object's strand)

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <chrono>
#include <functional>
#include <vector>

#include "fleet_placement.h"
#include "heartbeat_schedule.h"
#include "ricochet/db/db_worker.h"
#include "ricochet/db/fleet_records.h"

namespace ricochet::server {

class MatchRegistry;

/// What a heartbeat writes: the row (heartbeat_ms is set by the database call) and the matches.
struct DirectoryEntry {
  db::GameServerRow server;
  std::vector<db::HostedMatch> matches;
};

class DirectoryHeartbeat {
 public:
  /// Called on this object's strand at each beat.
  using Describe = std::function<DirectoryEntry()>;

  /// `period_us` between beats, `ttl_us` after which the directory drops a row. Every
  /// reference must outlive this object; nothing happens before start().
  DirectoryHeartbeat(boost::asio::io_context& io, db::DbWorker& db, MatchRegistry& matches,
                     PlacementCounters& counters, proto::TimeUs period_us, proto::TimeUs ttl_us,
                     Describe describe);

  void start();
  /// A match ended or opened here: beat sooner (HeartbeatSchedule::changed). Any thread.
  void matches_changed();
  /// Stops the beats and deletes the row, waiting for the database at most `wait` (the DB
  /// worker must still run). True when the row was deleted (or there was none).
  bool leave(std::chrono::milliseconds wait);

 private:
  void arm();
  void beat();

  boost::asio::strand<boost::asio::io_context::executor_type> strand_;
  boost::asio::steady_timer timer_;
  db::DbWorker& db_;
  MatchRegistry& matches_;
  PlacementCounters& counters_;
  HeartbeatSchedule schedule_;
  Describe describe_;
  std::string server_id_;  ///< the last row's, for leave()
};

}  // namespace ricochet::server
