#pragma once
/// Placement over any Store: the fleet directory that game servers sharing one database keep
/// with heartbeats, and the assignment of a player to a seat on one of them, with a short-lived
/// ticket the player presents when joining there (Open Match's names: ticket, assignment).
///
///   heartbeat     validates the server's row and its matches (InvalidPlacement: ids, host,
///                 ports 1..65535, certificate SHA-256 as 64 lowercase hex, version, capacity,
///                 players, mode and map names, match ids unique, counted_ms 0..now), then
///                 in one transaction writes the row with heartbeat_ms = now (and counted_ms
///                 = now when 0) and replaces its matches wholesale
///   leave         a server stopping: its row, its matches and its unclaimed tickets go
///   live_servers  the rows with heartbeat_ms > now - server_ttl_ms, by server_id
///   directory     those rows and their hosted matches (what GET /fleet shows)
///   purge_stale   deletes the servers that are not live, with their matches and all their
///                 tickets, and every expired ticket
///   assign        under the fleet-wide write lock (Store::transaction), so that two servers
///                 cannot both hand out the last seat:
///                   1. the account's unclaimed tickets are dropped (one open ticket each)
///                   2. seats: a match's free seats are its capacity less its players less its
///                      held seats; a server's the same over all its matches and its tickets
///                      for new matches. A ticket holds a seat while open (unclaimed,
///                      unexpired) and, once claimed, until its server's heartbeat counts the
///                      player: claimed_ms >= the row's counted_ms. (A claimed player is
///                      seated only after the claim; a heartbeat's figures taken before that
///                      would not count it, and a ticket that stopped holding at the claim
///                      left its seat free to a second assignment: a burst of tickets piled
///                      onto one match and got MATCH_FULL.)
///                   3. the open match of that mode (and map, if given) on a live server with a
///                      free seat on both, fullest first (players fill matches rather than
///                      spread), then on the least loaded server ((players + tickets) /
///                      capacity), then by server id and match id
///                   4. else a new match (match_id 0) on the live server hosting that mode (and
///                      map) with the most free seats, then the least loaded, then by id
///                   5. else NoServerAvailable (no live server, or none with a seat), or
///                      UnknownModeOrMap when no live server hosts a match of that mode (and map)
///                 and inserts the ticket: only the SHA-256 of its random 256-bit token is
///                 stored; the token is in the Assignment, shown to the client once.
///   claim         the server the client joins takes the ticket, once, in one statement
///                 (claimed only if unclaimed, for this server and account, and unexpired);
///                 otherwise UnknownTicket (unknown, malformed, already claimed, another
///                 server's or another account's) or ExpiredTicket, with the reason
///   held_seats    the held seats on one server, per match (HeldSeats::claimed of them by
///                 claimed tickets, which the server itself already counts or is seating)
///
/// Time is a parameter (Unix ms) of every call that needs it; the rows and times in the directory
/// are what each server wrote, so the TTL must be well above the clock skew between servers.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "ricochet/db/fleet_records.h"
#include "ricochet/db/records.h"
#include "ricochet/db/refusals.h"
#include "ricochet/db/result.h"
#include "ricochet/db/store.h"

namespace ricochet::db {

struct PlacementOptions {
  /// A server whose last heartbeat is this old is not live (not listed, not assigned to, and
  /// purged): a few heartbeat periods. 1 ms to 1 hour.
  UnixMillis server_ttl_ms = 15'000;
  /// How long a ticket stays open (holds its seat, may be claimed). 1 ms to 1 hour.
  UnixMillis ticket_lifetime_ms = 30'000;
  OnRefusal on_refusal;  ///< see refusals.h
};

/// Where a client is to play: the server (reach it and check its certificate), the match, and
/// the ticket's token to present there.
struct Assignment {
  std::string server_id;
  std::string host;
  std::int32_t control_port = 0;
  std::int32_t game_port = 0;
  std::string certificate_sha256;  ///< 64 lowercase hex digits
  MatchId match_id = 0;            ///< the server's match id; 0: a new match is made there
  std::string mode;
  std::string map;    ///< empty: a new match on a map of the server's choosing
  std::string token;  ///< 64 lowercase hex digits; shown once, only its SHA-256 is stored
  UnixMillis expires_ms = 0;
};

/// What purge_stale deleted.
struct Purged {
  std::int64_t servers = 0;
  std::int64_t tickets = 0;  ///< expired ones (stale servers' tickets go with them, uncounted)
};

class Placement {
 public:
  /// The store must outlive this object.
  explicit Placement(Store& store, PlacementOptions options = {});

  DbStatus heartbeat(const GameServerRow& server, const std::vector<HostedMatch>& matches,
                     UnixMillis now);
  /// Whether the server had a row.
  DbResult<bool> leave(std::string_view server_id);
  DbResult<std::vector<GameServerRow>> live_servers(UnixMillis now);
  DbResult<FleetDirectory> directory(UnixMillis now);
  DbResult<Purged> purge_stale(UnixMillis now);
  /// `map` empty: any map.
  DbResult<Assignment> assign(AccountId account, std::string_view mode, std::string_view map,
                              UnixMillis now);
  /// What the ticket was for (match_id 0: make a new match of that mode and map).
  DbResult<ClaimedTicket> claim(std::string_view token, std::string_view server_id,
                                AccountId account, UnixMillis now);
  /// Per match of the server (match_id 0: new matches), by match id; only matches with seats
  /// held are listed.
  DbResult<std::vector<HeldSeats>> held_seats(std::string_view server_id, UnixMillis now);

  const Refusals& refusals() const { return refusals_; }

 private:
  /// InvalidPlacement when an option is out of range, so a bad config refuses every call.
  DbStatus check_options() const;

  Store& store_;
  PlacementOptions options_;
  Refusals refusals_;
};

}  // namespace ricochet::db
