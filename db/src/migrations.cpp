/// Schema migrations (migrations.h).
///
/// Tables are STRICT: a value of the wrong type is refused when written instead of being stored
/// as whatever it happens to be. Times are Unix milliseconds, damage in hit points, durations in
/// seconds.

#include "migrations.h"

#include <array>

#include "ricochet/db/store.h"
#include "sqlite_handle.h"

namespace ricochet::db {

namespace {

// Version 1. Leaderboard indexes, checked with EXPLAIN QUERY PLAN on 100 000 accounts (SQLite
// 3.40; see leaderboard_sql.h for the queries):
//   - rating and kills: the top-N query scans (rating DESC, account_id) / (kills DESC,
//     account_id) in order and stops after N rows, no sort; counting the accounts above a value
//     (rank) is a range search on the same index, covering.
//   - win rate: a partial index cannot take min_matches as a parameter, so the index is on the
//     expression (the query must spell it exactly the same: CAST(wins AS REAL) / matches) and the
//     query filters matches >= ? while scanning it in order. matches is the index's last column
//     so that filter is checked on the index entry before the table row is read: the top 10 with
//     only 10 of 100 000 accounts qualifying takes 5 ms instead of 41 ms without it, and the rank
//     count over 72 000 entries 7 ms instead of 43 ms.
// A player_stats row is written only by record_match, so every row has matches >= 1 (CHECK):
// the rating and kills boards need no filter.
constexpr const char* kSchemaV1 = R"sql(
CREATE TABLE accounts (
  id INTEGER PRIMARY KEY,
  username TEXT NOT NULL,
  username_key TEXT NOT NULL UNIQUE,
  password_hash TEXT NOT NULL,
  created_ms INTEGER NOT NULL,
  last_login_ms INTEGER,
  banned INTEGER NOT NULL DEFAULT 0 CHECK (banned IN (0, 1))
) STRICT;

CREATE TABLE sessions (
  token_hash BLOB NOT NULL PRIMARY KEY CHECK (length(token_hash) = 32),
  account_id INTEGER NOT NULL REFERENCES accounts(id) ON DELETE CASCADE,
  created_ms INTEGER NOT NULL,
  expires_ms INTEGER NOT NULL
) STRICT, WITHOUT ROWID;
CREATE INDEX sessions_by_expiry ON sessions(expires_ms);
CREATE INDEX sessions_by_account ON sessions(account_id);

CREATE TABLE matches (
  id INTEGER PRIMARY KEY,
  map TEXT NOT NULL,
  mode TEXT NOT NULL,
  started_ms INTEGER NOT NULL,
  ended_ms INTEGER NOT NULL,
  tick_rate INTEGER NOT NULL
) STRICT;

CREATE TABLE match_players (
  match_id INTEGER NOT NULL REFERENCES matches(id) ON DELETE CASCADE,
  account_id INTEGER NOT NULL REFERENCES accounts(id),
  kills INTEGER NOT NULL,
  deaths INTEGER NOT NULL,
  score INTEGER NOT NULL,
  shots INTEGER NOT NULL,
  hits INTEGER NOT NULL,
  damage_dealt REAL NOT NULL,
  damage_taken REAL NOT NULL,
  seconds_played REAL NOT NULL,
  rating_before REAL NOT NULL,
  rating_after REAL NOT NULL,
  PRIMARY KEY (match_id, account_id)
) STRICT, WITHOUT ROWID;
CREATE INDEX match_players_by_account ON match_players(account_id);

CREATE TABLE player_stats (
  account_id INTEGER PRIMARY KEY REFERENCES accounts(id),
  matches INTEGER NOT NULL CHECK (matches >= 1),
  wins INTEGER NOT NULL DEFAULT 0,
  kills INTEGER NOT NULL DEFAULT 0,
  deaths INTEGER NOT NULL DEFAULT 0,
  score INTEGER NOT NULL DEFAULT 0,
  shots INTEGER NOT NULL DEFAULT 0,
  hits INTEGER NOT NULL DEFAULT 0,
  damage_dealt REAL NOT NULL DEFAULT 0,
  damage_taken REAL NOT NULL DEFAULT 0,
  seconds_played REAL NOT NULL DEFAULT 0,
  rating REAL NOT NULL DEFAULT 1500
) STRICT;
CREATE INDEX player_stats_by_rating ON player_stats(rating DESC, account_id);
CREATE INDEX player_stats_by_kills ON player_stats(kills DESC, account_id);
CREATE INDEX player_stats_by_win_rate
  ON player_stats((CAST(wins AS REAL) / matches) DESC, account_id, matches);
)sql";

// Version 2. Failed logins, so that the rate limits hold across every server process sharing
// the database. A key is "account:<username key>" or "address:<client address>". Counting a
// key's recent failures is a range search on (key, at_ms); dropping the old ones on at_ms.
constexpr const char* kSchemaV2 = R"sql(
CREATE TABLE login_failures (
  id INTEGER PRIMARY KEY,
  key TEXT NOT NULL,
  at_ms INTEGER NOT NULL
) STRICT;
CREATE INDEX login_failures_by_key ON login_failures(key, at_ms);
CREATE INDEX login_failures_by_time ON login_failures(at_ms);
)sql";

// Version 3. Team deathmatch and aborted matches: a match's team scores and whether it was
// stopped before its end, each player's team (0 in free-for-all). Rows written before it are
// free-for-all matches that ended normally, which the defaults say. Only columns are added, so
// the upgrade is quick and old rows are not rewritten.
constexpr const char* kSchemaV3 = R"sql(
ALTER TABLE matches ADD COLUMN aborted INTEGER NOT NULL DEFAULT 0 CHECK (aborted IN (0, 1));
ALTER TABLE matches ADD COLUMN red_score INTEGER NOT NULL DEFAULT 0;
ALTER TABLE matches ADD COLUMN blue_score INTEGER NOT NULL DEFAULT 0;
ALTER TABLE match_players ADD COLUMN team INTEGER NOT NULL DEFAULT 0 CHECK (team IN (0, 1, 2));
)sql";

// Version 4. Each match's uuid (MatchRecord::uuid), by which record_match finds a match already
// written instead of writing it twice. Unique through an index (SQLite cannot add a UNIQUE
// column); rows written before it keep a NULL uuid, and NULLs are all distinct in a unique index.
// Looking a uuid up is a search of that index.
constexpr const char* kSchemaV4 = R"sql(
ALTER TABLE matches ADD COLUMN uuid TEXT
  CHECK (uuid IS NULL OR (length(uuid) = 32 AND uuid NOT GLOB '*[^0-9a-f]*'));
CREATE UNIQUE INDEX matches_by_uuid ON matches(uuid);
)sql";

// Version 5. Placement (placement.h): the fleet directory, one row per game server (replaced at
// each heartbeat, with its hosted matches), and the tickets of assignments, keyed by the SHA-256 of
// their token. A ticket names its server without a foreign key: a server that leaves deletes
// its unclaimed tickets only, the claimed ones go when they expire. Live servers are a range on
// heartbeat_ms; an account's tickets, a server's, and the expired ones each have an index.
constexpr const char* kSchemaV5 = R"sql(
CREATE TABLE game_servers (
  server_id TEXT NOT NULL PRIMARY KEY,
  host TEXT NOT NULL,
  control_port INTEGER NOT NULL CHECK (control_port BETWEEN 1 AND 65535),
  game_port INTEGER NOT NULL CHECK (game_port BETWEEN 1 AND 65535),
  certificate_sha256 TEXT NOT NULL CHECK (length(certificate_sha256) = 64),
  version TEXT NOT NULL,
  capacity INTEGER NOT NULL CHECK (capacity >= 1),
  players INTEGER NOT NULL CHECK (players >= 0),
  heartbeat_ms INTEGER NOT NULL,
  started_ms INTEGER NOT NULL
) STRICT, WITHOUT ROWID;
CREATE INDEX game_servers_by_heartbeat ON game_servers(heartbeat_ms);

CREATE TABLE game_server_matches (
  server_id TEXT NOT NULL REFERENCES game_servers(server_id) ON DELETE CASCADE,
  match_id INTEGER NOT NULL CHECK (match_id >= 1),
  mode TEXT NOT NULL,
  map TEXT NOT NULL,
  players INTEGER NOT NULL CHECK (players >= 0),
  capacity INTEGER NOT NULL CHECK (capacity >= 1),
  open INTEGER NOT NULL CHECK (open IN (0, 1)),
  PRIMARY KEY (server_id, match_id)
) STRICT, WITHOUT ROWID;

CREATE TABLE tickets (
  token_hash BLOB NOT NULL PRIMARY KEY CHECK (length(token_hash) = 32),
  account_id INTEGER NOT NULL REFERENCES accounts(id) ON DELETE CASCADE,
  server_id TEXT NOT NULL,
  match_id INTEGER NOT NULL CHECK (match_id >= 0),
  mode TEXT NOT NULL,
  map TEXT NOT NULL,
  created_ms INTEGER NOT NULL,
  expires_ms INTEGER NOT NULL,
  claimed_ms INTEGER
) STRICT, WITHOUT ROWID;
CREATE INDEX tickets_by_account ON tickets(account_id);
CREATE INDEX tickets_by_server ON tickets(server_id, match_id);
CREATE INDEX tickets_by_expiry ON tickets(expires_ms);
)sql";

// Version 6. When a server's heartbeat figures were complete (GameServerRow::counted_ms): a
// ticket claimed since holds its seat until a heartbeat counts its player. 0 for rows written
// before: their claimed tickets hold until the server's next heartbeat.
constexpr const char* kSchemaV6 = R"sql(
ALTER TABLE game_servers ADD COLUMN counted_ms INTEGER NOT NULL DEFAULT 0;
)sql";

// Version 7. Where each server's admin port is (GameServerRow::admin_port), so that tools and
// other servers can read /metrics and /fleet; 0 (not advertised) for rows written before.
constexpr const char* kSchemaV7 = R"sql(
ALTER TABLE game_servers ADD COLUMN admin_port INTEGER NOT NULL DEFAULT 0
  CHECK (admin_port BETWEEN 0 AND 65535);
)sql";

constexpr std::array kMigrations = {
    Migration{1, "accounts, sessions, matches, player stats and leaderboard indexes", kSchemaV1},
    Migration{2, "failed logins for rate limits shared by every server process", kSchemaV2},
    Migration{3, "team deathmatch (teams, team scores) and aborted matches", kSchemaV3},
    Migration{4, "a unique uuid per match, so that a result is written once", kSchemaV4},
    Migration{5, "placement: the fleet directory of game servers and tickets", kSchemaV5},
    Migration{6, "placement: claimed tickets hold their seat until a heartbeat counts them",
              kSchemaV6},
    Migration{7, "placement: the directory row says where the server's admin port is", kSchemaV7},
};

DbResult<int> read_user_version(sqlite3* db, const std::string& path) {
  std::int64_t version = 0;
  const int rc = sqlite::single_integer(db, "PRAGMA user_version", version);
  if (rc != SQLITE_OK) return sqlite::error_from(db, rc, path, "reading the schema version");
  return static_cast<int>(version);  // user_version is a 32-bit field of the header
}

DbStatus apply(sqlite3* db, const std::string& path, const Migration& migration) {
  const std::string what =
      "schema migration " + std::to_string(migration.version) + " (" + migration.summary + ")";
  sqlite::Transaction transaction(db);
  if (const int rc = transaction.begin(); rc != SQLITE_OK)
    return sqlite::error_from(db, rc, path, what);
  auto version = read_user_version(db, path);
  if (!version) return version.error();
  if (version.value() >= migration.version) return {};  // another process got there first
  if (const int rc = sqlite::exec(db, migration.sql); rc != SQLITE_OK)
    return sqlite::error_from(db, rc, path, what);
  // PRAGMA takes no parameters; the number is this binary's own constant.
  const std::string set_version = "PRAGMA user_version = " + std::to_string(migration.version);
  if (const int rc = sqlite::exec(db, set_version.c_str()); rc != SQLITE_OK)
    return sqlite::error_from(db, rc, path, what);
  if (const int rc = transaction.commit(); rc != SQLITE_OK)
    return sqlite::error_from(db, rc, path, what);
  return {};
}

}  // namespace

std::span<const Migration> sqlite_migrations() {
  return kMigrations;
}

int sqlite_schema_version() {
  return kMigrations.back().version;
}

DbResult<int> read_schema_version(sqlite3* db, const std::string& path) {
  auto version = read_user_version(db, path);
  if (!version) return version;
  if (version.value() > sqlite_schema_version()) {
    return DbError{DbErrorCode::SchemaTooNew,
                   path + " has schema version " + std::to_string(version.value()) +
                       "; this build knows up to " + std::to_string(sqlite_schema_version()) +
                       "; upgrade Ricochet"};
  }
  if (version.value() < 0) {
    return DbError{DbErrorCode::CorruptDatabase,
                   path + " has schema version " + std::to_string(version.value()) +
                       ", which no Ricochet writes; restore it from a backup or move it away"};
  }
  return version;
}

DbStatus apply_migrations(sqlite3* db, const std::string& path) {
  auto version = read_schema_version(db, path);
  if (!version) return version.error();
  for (const Migration& migration : kMigrations) {
    if (migration.version <= version.value()) continue;
    if (DbStatus status = apply(db, path, migration); !status) return status;
  }
  // A newer binary may have migrated the file further between the reads above.
  if (auto final_version = read_schema_version(db, path); !final_version)
    return final_version.error();
  return {};
}

}  // namespace ricochet::db
