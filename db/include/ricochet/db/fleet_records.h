#pragma once
/// What the store keeps for placement (placement.h has the rules): the fleet directory, one row
/// per game server with the matches it hosts, and the tickets of assignments. Times are Unix
/// milliseconds passed in by the caller; ids of hosted matches are the hosting server's own.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "ricochet/db/records.h"

namespace ricochet::db {

/// A game server's directory row, as its last heartbeat wrote it.
struct GameServerRow {
  std::string server_id;  ///< drawn at random by the server at start: 1–64 of [A-Za-z0-9_-]
  std::string host;       ///< what clients connect to: a DNS name or an IP address
  std::int32_t control_port = 0;   ///< the TLS control channel (TCP), 1..65535
  std::int32_t game_port = 0;      ///< the game channel (UDP), 1..65535
  std::string certificate_sha256;  ///< the control channel certificate's, 64 lowercase hex digits
  std::string version;             ///< the server's build, 1–64 printable ASCII characters
  std::int32_t capacity = 0;       ///< seats on the whole server (players), at least 1
  std::int32_t players = 0;        ///< seated now, 0..capacity
  UnixMillis heartbeat_ms = 0;     ///< when the server last wrote the row
  UnixMillis started_ms = 0;       ///< when the server started
  /// The server's clock when its players and matches were complete: every ticket claimed
  /// before it is seated in them (or its join failed), one claimed at or after it may not be
  /// yet and keeps holding its seat (placement.h, held seats). 0..heartbeat_ms; 0 in a
  /// heartbeat means as of the heartbeat.
  UnixMillis counted_ms = 0;
  /// The admin HTTP port (/metrics, /fleet; TCP) reachable at `host`, 1..65535; 0: not
  /// advertised (the admin port is loopback-only unless bound wider: OPERATIONS.md).
  std::int32_t admin_port = 0;
};

/// One match a game server hosts, as its last heartbeat described it.
struct HostedMatch {
  MatchId match_id = 0;       ///< the hosting server's id for it, at least 1
  std::string mode;           ///< "ffa", "tdm": 1–32 of [a-z0-9_-]
  std::string map;            ///< 1–64 of [A-Za-z0-9_.-]
  std::int32_t players = 0;   ///< seated now, 0..capacity
  std::int32_t capacity = 0;  ///< seats, at least 1
  bool open = false;          ///< joinable (not ending or reserved)
};

/// A hosted match with the server it is on, as the directory lists them.
struct DirectoryMatch {
  std::string server_id;
  HostedMatch match;
};

/// The live part of the directory: the servers and the matches they host, each by server id
/// (then match id). Read in two statements: a match whose server's row is not in `servers`
/// (it beat in between) is to be passed over.
struct FleetDirectory {
  std::vector<GameServerRow> servers;
  std::vector<DirectoryMatch> matches;
};

/// A ticket: the right to one seat on one server, shown to its client once as a random token,
/// of which only the SHA-256 is kept.
struct TicketRow {
  std::string token_hash;  ///< SHA-256 of the token, 32 bytes
  AccountId account = 0;
  std::string server_id;
  MatchId match_id = 0;  ///< the hosting server's match id; 0: a new match is to be made
  std::string mode;
  std::string map;  ///< empty: the server picks (a new match with no map asked for)
  UnixMillis created_ms = 0;
  UnixMillis expires_ms = 0;
  std::optional<UnixMillis> claimed_ms;  ///< when the server took it; nullopt while unclaimed
};

/// Seats held on one match of one server by open (unclaimed, unexpired) tickets and by tickets
/// claimed there that the server's last heartbeat had not counted yet (claimed_ms >= its
/// counted_ms).
struct HeldSeats {
  std::string server_id;
  MatchId match_id = 0;  ///< 0: tickets for a new match on that server
  std::int64_t seats = 0;
  std::int64_t claimed = 0;  ///< of `seats`, those of claimed tickets not yet counted
};

/// What a claimed ticket was for.
struct ClaimedTicket {
  MatchId match_id = 0;  ///< 0: make a new match of this mode and map
  std::string mode;
  std::string map;  ///< empty: any map the server hosts the mode on
};

}  // namespace ricochet::db
