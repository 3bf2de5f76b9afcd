#pragma once
/// When the server writes its row in the fleet directory (placement), sans-IO: the time comes
/// in, the decisions go out; an Asio timer in server.cpp only wakes it at next_at().
///
///   idle ──start(now) at next_at()──▶ writing ──finished(ok, now)──▶ idle
///   any ──stop()──▶ stopped (final: the server left the directory)
///
/// One write at a time: a slow database delays the next beat instead of queueing beats. The
/// next beat is one period after the last began, written or not (a failed write is retried at
/// the same pace), or sooner when the matches changed (changed()). The directory lists the server
/// while its last written beat is younger than the TTL; finished() reports when that starts and
/// when it ends, for a log line each.

#include <cstdint>
#include <optional>

#include "ricochet/proto/clock.h"

namespace ricochet::server {

/// What a finished heartbeat changed in whether the directory lists this server.
enum class DirectoryListing : std::uint8_t {
  Unchanged,
  Listed,  ///< written after none was, or after the row had gone stale
  Lost,    ///< a write failed and the last written one is older than the TTL
};

class HeartbeatSchedule {
 public:
  /// `period_us` between beats, `ttl_us` after which the directory drops a row (> period).
  /// The first beat is due at `now`.
  HeartbeatSchedule(proto::TimeUs period_us, proto::TimeUs ttl_us, proto::TimeUs now);

  /// True when a beat is to be written now (due, none in flight, not stopped): it is then in
  /// flight until finished().
  bool start(proto::TimeUs now);
  /// The beat in flight came back; `written`: the database took it.
  DirectoryListing finished(bool written, proto::TimeUs now);
  /// When start() next says yes; nothing while a beat is in flight or once stopped.
  std::optional<proto::TimeUs> next_at() const;
  /// A match ended or opened: the next beat is due now, but not before a quarter period after
  /// the last began (a burst of changes costs at most four beats a period). The directory then
  /// stops listing an ended match within that, not a whole period later.
  void changed(proto::TimeUs now);
  /// Leaving the directory: no beat from now on.
  void stop() { stopped_ = true; }
  bool stopped() const { return stopped_; }
  /// Whether the directory lists this server at `now`, as far as this server knows.
  bool listed(proto::TimeUs now) const;

 private:
  proto::TimeUs period_us_;
  proto::TimeUs ttl_us_;
  proto::TimeUs next_at_;
  std::optional<proto::TimeUs> in_flight_since_;
  std::optional<proto::TimeUs> last_began_;
  std::optional<proto::TimeUs> last_written_;  ///< when the last written beat began
  bool reported_listed_ = false;
  bool stopped_ = false;
};

}  // namespace ricochet::server
