/// PostgreSQL schema migrations (postgres_migrations.h).
///
/// The same tables, columns, constraints and indexes as the SQLite schema of the same version
/// (migrations.cpp, where the indexes are explained), in PostgreSQL's types: every integer is a
/// BIGINT (SQLite's INTEGER is 64-bit), every REAL a DOUBLE PRECISION (PostgreSQL's REAL is
/// 32-bit), flags stay 0/1 integers so that one SQL text reads both. Times are Unix
/// milliseconds, damage in hit points, durations in seconds.

#include "postgres_migrations.h"

#include <array>

#include "postgres_handle.h"
#include "ricochet/db/store.h"

namespace ricochet::db {

namespace {

// Version 1. The win-rate index is on the expression the leaderboard query spells exactly the
// same (leaderboard_sql.h, postgres_top).
constexpr const char* kSchemaV1 = R"sql(
CREATE TABLE accounts (
  id BIGINT GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
  username TEXT NOT NULL,
  username_key TEXT NOT NULL UNIQUE,
  password_hash TEXT NOT NULL,
  created_ms BIGINT NOT NULL,
  last_login_ms BIGINT,
  banned BIGINT NOT NULL DEFAULT 0 CHECK (banned IN (0, 1))
);

CREATE TABLE sessions (
  token_hash BYTEA NOT NULL PRIMARY KEY CHECK (length(token_hash) = 32),
  account_id BIGINT NOT NULL REFERENCES accounts(id) ON DELETE CASCADE,
  created_ms BIGINT NOT NULL,
  expires_ms BIGINT NOT NULL
);
CREATE INDEX sessions_by_expiry ON sessions(expires_ms);
CREATE INDEX sessions_by_account ON sessions(account_id);

CREATE TABLE matches (
  id BIGINT GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
  map TEXT NOT NULL,
  mode TEXT NOT NULL,
  started_ms BIGINT NOT NULL,
  ended_ms BIGINT NOT NULL,
  tick_rate BIGINT NOT NULL
);

CREATE TABLE match_players (
  match_id BIGINT NOT NULL REFERENCES matches(id) ON DELETE CASCADE,
  account_id BIGINT NOT NULL REFERENCES accounts(id),
  kills BIGINT NOT NULL,
  deaths BIGINT NOT NULL,
  score BIGINT NOT NULL,
  shots BIGINT NOT NULL,
  hits BIGINT NOT NULL,
  damage_dealt DOUBLE PRECISION NOT NULL,
  damage_taken DOUBLE PRECISION NOT NULL,
  seconds_played DOUBLE PRECISION NOT NULL,
  rating_before DOUBLE PRECISION NOT NULL,
  rating_after DOUBLE PRECISION NOT NULL,
  PRIMARY KEY (match_id, account_id)
);
CREATE INDEX match_players_by_account ON match_players(account_id);

CREATE TABLE player_stats (
  account_id BIGINT PRIMARY KEY REFERENCES accounts(id),
  matches BIGINT NOT NULL CHECK (matches >= 1),
  wins BIGINT NOT NULL DEFAULT 0,
  kills BIGINT NOT NULL DEFAULT 0,
  deaths BIGINT NOT NULL DEFAULT 0,
  score BIGINT NOT NULL DEFAULT 0,
  shots BIGINT NOT NULL DEFAULT 0,
  hits BIGINT NOT NULL DEFAULT 0,
  damage_dealt DOUBLE PRECISION NOT NULL DEFAULT 0,
  damage_taken DOUBLE PRECISION NOT NULL DEFAULT 0,
  seconds_played DOUBLE PRECISION NOT NULL DEFAULT 0,
  rating DOUBLE PRECISION NOT NULL DEFAULT 1500
);
CREATE INDEX player_stats_by_rating ON player_stats(rating DESC, account_id);
CREATE INDEX player_stats_by_kills ON player_stats(kills DESC, account_id);
CREATE INDEX player_stats_by_win_rate
  ON player_stats((CAST(wins AS DOUBLE PRECISION) / matches) DESC, account_id, matches);
)sql";

// Version 2. Failed logins, shared by every server process on the database.
constexpr const char* kSchemaV2 = R"sql(
CREATE TABLE login_failures (
  id BIGINT GENERATED ALWAYS AS IDENTITY PRIMARY KEY,
  key TEXT NOT NULL,
  at_ms BIGINT NOT NULL
);
CREATE INDEX login_failures_by_key ON login_failures(key, at_ms);
CREATE INDEX login_failures_by_time ON login_failures(at_ms);
)sql";

// Version 3. Team deathmatch and aborted matches (columns with defaults: no rows rewritten).
constexpr const char* kSchemaV3 = R"sql(
ALTER TABLE matches ADD COLUMN aborted BIGINT NOT NULL DEFAULT 0 CHECK (aborted IN (0, 1));
ALTER TABLE matches ADD COLUMN red_score BIGINT NOT NULL DEFAULT 0;
ALTER TABLE matches ADD COLUMN blue_score BIGINT NOT NULL DEFAULT 0;
ALTER TABLE match_players ADD COLUMN team BIGINT NOT NULL DEFAULT 0 CHECK (team IN (0, 1, 2));
)sql";

// Version 4. Each match's uuid, unique; old rows keep NULL (migrations.cpp).
constexpr const char* kSchemaV4 = R"sql(
ALTER TABLE matches ADD COLUMN uuid TEXT CHECK (uuid ~ '^[0-9a-f]{32}$');
CREATE UNIQUE INDEX matches_by_uuid ON matches(uuid);
)sql";

// Version 5. Placement: the fleet directory and tickets (migrations.cpp says why no foreign key
// names a ticket's server).
constexpr const char* kSchemaV5 = R"sql(
CREATE TABLE game_servers (
  server_id TEXT NOT NULL PRIMARY KEY,
  host TEXT NOT NULL,
  control_port BIGINT NOT NULL CHECK (control_port BETWEEN 1 AND 65535),
  game_port BIGINT NOT NULL CHECK (game_port BETWEEN 1 AND 65535),
  certificate_sha256 TEXT NOT NULL CHECK (length(certificate_sha256) = 64),
  version TEXT NOT NULL,
  capacity BIGINT NOT NULL CHECK (capacity >= 1),
  players BIGINT NOT NULL CHECK (players >= 0),
  heartbeat_ms BIGINT NOT NULL,
  started_ms BIGINT NOT NULL
);
CREATE INDEX game_servers_by_heartbeat ON game_servers(heartbeat_ms);

CREATE TABLE game_server_matches (
  server_id TEXT NOT NULL REFERENCES game_servers(server_id) ON DELETE CASCADE,
  match_id BIGINT NOT NULL CHECK (match_id >= 1),
  mode TEXT NOT NULL,
  map TEXT NOT NULL,
  players BIGINT NOT NULL CHECK (players >= 0),
  capacity BIGINT NOT NULL CHECK (capacity >= 1),
  open BIGINT NOT NULL CHECK (open IN (0, 1)),
  PRIMARY KEY (server_id, match_id)
);

CREATE TABLE tickets (
  token_hash BYTEA NOT NULL PRIMARY KEY CHECK (length(token_hash) = 32),
  account_id BIGINT NOT NULL REFERENCES accounts(id) ON DELETE CASCADE,
  server_id TEXT NOT NULL,
  match_id BIGINT NOT NULL CHECK (match_id >= 0),
  mode TEXT NOT NULL,
  map TEXT NOT NULL,
  created_ms BIGINT NOT NULL,
  expires_ms BIGINT NOT NULL,
  claimed_ms BIGINT
);
CREATE INDEX tickets_by_account ON tickets(account_id);
CREATE INDEX tickets_by_server ON tickets(server_id, match_id);
CREATE INDEX tickets_by_expiry ON tickets(expires_ms);
)sql";

// Version 6. When a server's heartbeat figures were complete (migrations.cpp).
constexpr const char* kSchemaV6 = R"sql(
ALTER TABLE game_servers ADD COLUMN counted_ms BIGINT NOT NULL DEFAULT 0;
)sql";

// Version 7. Where each server's admin port is; 0: not advertised (migrations.cpp).
constexpr const char* kSchemaV7 = R"sql(
ALTER TABLE game_servers ADD COLUMN admin_port BIGINT NOT NULL DEFAULT 0
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

/// The one-row version table; made inside the first migration's locked transaction.
constexpr const char* kVersionTable =
    "CREATE TABLE IF NOT EXISTS schema_version ("
    " one_row BOOLEAN PRIMARY KEY DEFAULT TRUE CHECK (one_row),"
    " version INTEGER NOT NULL)";

/// The version row; 0 when the table or its row does not exist yet.
DbResult<int> read_version(PGconn* conn, const std::string& where) {
  postgres::Result r = postgres::exec(conn, "SELECT version FROM schema_version");
  if (!r.ok() && r.sqlstate() == "42P01") return 0;  // undefined_table: a new database
  if (!r.ok()) return postgres::error_from(conn, r, where, "reading the schema version");
  if (r.rows() == 0) return 0;
  const std::int64_t version = r.integer(0, 0);
  if (!r.column_error().empty())
    return DbError{DbErrorCode::CorruptDatabase, where + ": schema_version: " + r.column_error()};
  return static_cast<int>(version);
}

DbStatus apply(PGconn* conn, const std::string& where, const Migration& migration) {
  const std::string what =
      "schema migration " + std::to_string(migration.version) + " (" + migration.summary + ")";
  postgres::Transaction transaction(conn);
  if (postgres::Result r = transaction.begin(); r.get())
    return postgres::error_from(conn, r, where, what);
  if (postgres::Result r = postgres::exec(conn, kVersionTable); !r.ok())
    return postgres::error_from(conn, r, where, what);
  auto version = read_version(conn, where);
  if (!version) return version.error();
  if (version.value() >= migration.version) return {};  // another server got there first
  if (postgres::Result r = postgres::exec(conn, migration.sql); !r.ok())
    return postgres::error_from(conn, r, where, what);
  // The number is this binary's own constant, not a value from outside.
  const std::string set_version =
      "INSERT INTO schema_version (version) VALUES (" + std::to_string(migration.version) +
      ") ON CONFLICT (one_row) DO UPDATE SET version = excluded.version";
  if (postgres::Result r = postgres::exec(conn, set_version.c_str()); !r.ok())
    return postgres::error_from(conn, r, where, what);
  if (postgres::Result r = transaction.commit(); r.get())
    return postgres::error_from(conn, r, where, what);
  return {};
}

}  // namespace

std::span<const Migration> postgres_migrations() {
  return kMigrations;
}

int postgres_schema_version() {
  return kMigrations.back().version;
}

DbResult<int> read_postgres_schema_version(PGconn* conn, const std::string& where) {
  auto version = read_version(conn, where);
  if (!version) return version;
  if (version.value() > postgres_schema_version()) {
    return DbError{DbErrorCode::SchemaTooNew,
                   where + " has schema version " + std::to_string(version.value()) +
                       "; this build knows up to " + std::to_string(postgres_schema_version()) +
                       "; upgrade Ricochet"};
  }
  if (version.value() < 0) {
    return DbError{DbErrorCode::CorruptDatabase,
                   where + " has schema version " + std::to_string(version.value()) +
                       ", which no Ricochet writes; restore it from a backup"};
  }
  return version;
}

DbStatus apply_postgres_migrations(PGconn* conn, const std::string& where) {
  auto version = read_postgres_schema_version(conn, where);
  if (!version) return version.error();
  for (const Migration& migration : kMigrations) {
    if (migration.version <= version.value()) continue;
    if (DbStatus status = apply(conn, where, migration); !status) return status;
  }
  if (auto final_version = read_postgres_schema_version(conn, where); !final_version)
    return final_version.error();
  return {};
}

}  // namespace ricochet::db
