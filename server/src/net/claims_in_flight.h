#pragma once
/// The ticket joins between their claim and their seat, so that a directory heartbeat says up
/// to when its figures are complete (db::GameServerRow::counted_ms): the directory keeps a
/// ticket claimed at or after that time holding its seat, and lets the others go.
///
/// Why the oldest claim in flight, and why the clock is read under the lock: a join reads the
/// time it claims at (claimed_ms) and registers in one step; the heartbeat takes counted_as_of()
/// and only then the players. A claim older than what counted_as_of() returned was therefore not
/// in flight when it was taken (a later one would have read a later time), so its join had
/// already seated its player (or failed) before the players were taken: they count it. A claim
/// still in flight makes counted_as_of() no later than its own time, so its ticket holds on.
/// Claims made after the figures were taken, while the row is on its way to the database, are
/// later than counted_ms and hold too; the row and its matches are written in one transaction,
/// and assignments read them under the fleet-wide lock, so an assignment sees the figures and
/// the counted_ms that go with them. Both times are this server's clock (the claim is made
/// here), so the skew between servers plays no part. A wall clock stepped back only makes
/// claims look older: their seats are let go one heartbeat early, as before this existed.

#include <cstdint>
#include <functional>
#include <map>
#include <mutex>

#include "ricochet/db/records.h"

namespace ricochet::server {

class ClaimsInFlight {
 public:
  /// The server's Unix clock in ms (what claims and heartbeats are stamped with).
  using Clock = std::function<db::UnixMillis()>;

  explicit ClaimsInFlight(Clock clock);

  /// One claim from its start to the end of its join (seated or refused): the claim is to be
  /// made at claimed_ms(). Ends when destroyed.
  class Claim {
   public:
    Claim(const Claim&) = delete;
    Claim& operator=(const Claim&) = delete;
    ~Claim();
    db::UnixMillis claimed_ms() const { return claimed_ms_; }

   private:
    friend class ClaimsInFlight;
    Claim(ClaimsInFlight& owner, std::uint64_t id, db::UnixMillis claimed_ms)
        : owner_(owner), id_(id), claimed_ms_(claimed_ms) {}
    ClaimsInFlight& owner_;
    std::uint64_t id_;
    db::UnixMillis claimed_ms_;
  };

  /// Reads the clock and registers the claim, at once.
  [[nodiscard]] Claim begin();
  /// The time as of which every claim has been seated or refused: now, or the oldest claim
  /// still in flight. Take it before the players a heartbeat reports.
  db::UnixMillis counted_as_of() const;
  std::size_t in_flight() const;

 private:
  void end(std::uint64_t id);

  Clock clock_;
  mutable std::mutex mutex_;
  std::uint64_t next_id_ = 0;
  std::map<std::uint64_t, db::UnixMillis> claimed_ms_;  ///< by id
};

}  // namespace ricochet::server
