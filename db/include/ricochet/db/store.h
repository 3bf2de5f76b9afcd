#pragma once
/// The persistence interface: what the server needs from a database, and nothing about how.
///
/// SQLite (open_sqlite_store) is the embedded default: one file, no server. PostgreSQL
/// (open_postgres_store), for operators running many server processes on one database,
/// implements the same interface; open_store picks one by the form of its URL. Every
/// call is synchronous and may block on the disk: the game thread never calls a Store directly,
/// it goes through DbWorker (db_worker.h). One Store is used by one thread at a time.
///
/// A store only stores: it keeps what it must consistent (foreign keys, uniqueness,
/// transactions) and decides nothing. The rules live above it, the same for every backend: the
/// account rules (name syntax, password hashing, sessions, rate limits) in Accounts
/// (accounts.h), the match rules (validation, winners, Elo, ranks) in Matches (matches.h).

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "ricochet/db/fleet_records.h"
#include "ricochet/db/records.h"
#include "ricochet/db/result.h"

namespace ricochet::db {

class Store {
 public:
  virtual ~Store() = default;

  /// Runs `work` as one unit: the store calls it makes are committed together when it succeeds,
  /// and none of them is when it fails (or the commit does). The write lock is taken before
  /// `work` starts (SQLite: BEGIN IMMEDIATE; PostgreSQL: an advisory lock), so what it reads cannot
  /// change under it and it never fails half-way for another writer's lock. A transaction inside
  /// `work` joins this one. Busy when the lock is not had within the busy timeout.
  virtual DbStatus transaction(const std::function<DbStatus()>& work) = 0;

  // --- accounts ---
  /// DuplicateUsername when username_key (the lowercased name) is taken.
  virtual DbResult<AccountId> insert_account(std::string_view username,
                                             std::string_view username_key,
                                             std::string_view password_hash, UnixMillis now) = 0;
  virtual DbResult<std::optional<AccountCredentials>> find_account_by_key(
      std::string_view username_key) = 0;
  /// UnknownAccount when there is no such id.
  virtual DbResult<Account> account(AccountId id) = 0;
  virtual DbStatus set_password_hash(AccountId id, std::string_view password_hash) = 0;
  virtual DbStatus set_banned(AccountId id, bool banned) = 0;
  virtual DbStatus set_last_login(AccountId id, UnixMillis now) = 0;

  // --- sessions (keyed by the SHA-256 of the token, 32 bytes) ---
  virtual DbStatus insert_session(std::string_view token_hash, AccountId account,
                                  UnixMillis created_ms, UnixMillis expires_ms) = 0;
  virtual DbResult<std::optional<SessionRow>> find_session(std::string_view token_hash) = 0;
  virtual DbStatus delete_session(std::string_view token_hash) = 0;
  virtual DbStatus delete_sessions_of(AccountId account) = 0;
  /// Removes sessions that expired before `now`; returns how many.
  virtual DbResult<std::int64_t> delete_expired_sessions(UnixMillis now) = 0;

  // --- rate-limit events by key, for limits that every server process on the database shares:
  // failed logins ("account:<name>", "account-address:<name> <address>", "address:<address>")
  // and registrations ("registration:<address>"); the keys are the account rules' business ---
  /// Notes one failure under `key` at `at_ms`; returns its id.
  virtual DbResult<std::int64_t> insert_login_failure(std::string_view key, UnixMillis at_ms) = 0;
  /// How many failures under `key` were noted after `after_ms`.
  virtual DbResult<std::int64_t> count_login_failures(std::string_view key,
                                                      UnixMillis after_ms) = 0;
  virtual DbStatus delete_login_failure(std::int64_t id) = 0;
  virtual DbStatus delete_login_failures_of(std::string_view key) = 0;
  /// Removes every failure noted at or before `at_ms`.
  virtual DbStatus delete_login_failures_until(UnixMillis at_ms) = 0;

  // --- matches, stats, leaderboards ---
  /// The account's current rating; nullopt when it never played; UnknownAccount if none.
  virtual DbResult<std::optional<double>> rating_of(AccountId id) = 0;
  /// Writes the match (its uuid NULL when empty; Storage when another match has it), every
  /// player's result and outcome (outcomes[i] is players[i]'s), and adds them to the players'
  /// lifetime stats with their new ratings, in one transaction: after a crash either all of it is
  /// there or none.
  virtual DbResult<MatchId> insert_match(const MatchRecord& match,
                                         const std::vector<PlayerOutcome>& outcomes) = 0;
  /// The match written with this uuid (MatchRecord::uuid), nullopt when there is none.
  virtual DbResult<std::optional<StoredMatch>> find_match(std::string_view uuid) = 0;
  virtual DbResult<std::int64_t> match_count() = 0;
  /// Zeros and the initial rating for an account that never played; UnknownAccount if none.
  virtual DbResult<PlayerStats> player_stats(AccountId id) = 0;
  /// The first `limit` entries of the board, best first (ties by account id), unranked. Every
  /// account that played is on the Rating and Kills boards; WinRate lists only those with at
  /// least `min_matches` matches.
  virtual DbResult<std::vector<LeaderboardEntry>> leaderboard(LeaderboardKind kind, int limit,
                                                              std::int64_t min_matches) = 0;
  /// The account's username, matches and value on that board, unranked; nullopt when it never
  /// played; UnknownAccount if none.
  virtual DbResult<std::optional<LeaderboardEntry>> board_entry(AccountId id,
                                                                LeaderboardKind kind) = 0;
  /// How many entries of the board (WinRate: with at least `min_matches` matches) have a value
  /// above `value`.
  virtual DbResult<std::int64_t> count_better(LeaderboardKind kind, double value,
                                              std::int64_t min_matches) = 0;

  // --- fleet directory and tickets (the rules: placement.h) ---
  /// Inserts the server's row, or replaces every field of it (by server_id).
  virtual DbStatus upsert_game_server(const GameServerRow& server) = 0;
  /// Replaces every hosted match of the server with `matches`, in one transaction.
  virtual DbStatus replace_game_server_matches(std::string_view server_id,
                                               const std::vector<HostedMatch>& matches) = 0;
  /// The rows with heartbeat_ms > `heartbeat_after_ms`, by server_id.
  virtual DbResult<std::vector<GameServerRow>> game_servers(UnixMillis heartbeat_after_ms) = 0;
  /// The matches of the servers with heartbeat_ms > `heartbeat_after_ms`, by server then match.
  virtual DbResult<std::vector<DirectoryMatch>> directory_matches(
      UnixMillis heartbeat_after_ms) = 0;
  /// Deletes the server's row, its matches and its unclaimed tickets, in one transaction;
  /// whether there was a row.
  virtual DbResult<bool> delete_game_server(std::string_view server_id) = 0;
  /// Deletes the servers with heartbeat_ms <= `heartbeat_until_ms`, their matches and all their
  /// tickets, in one transaction; how many servers.
  virtual DbResult<std::int64_t> delete_game_servers_until(UnixMillis heartbeat_until_ms) = 0;
  /// UnknownAccount when the ticket's account does not exist.
  virtual DbStatus insert_ticket(const TicketRow& ticket) = 0;
  virtual DbResult<std::optional<TicketRow>> find_ticket(std::string_view token_hash) = 0;
  /// Unclaimed tickets with expires_ms > `now`, counted per server and match, by server then
  /// match.
  virtual DbResult<std::vector<HeldSeats>> held_seats(UnixMillis now) = 0;
  /// Deletes the account's unclaimed tickets; how many.
  virtual DbResult<std::int64_t> delete_unclaimed_tickets_of(AccountId account) = 0;
  /// Sets claimed_ms = `now` in one statement if the ticket is unclaimed, for this server and
  /// account, and expires after `now`; what it was for, or nullopt when any of that fails.
  virtual DbResult<std::optional<ClaimedTicket>> claim_ticket(std::string_view token_hash,
                                                              std::string_view server_id,
                                                              AccountId account,
                                                              UnixMillis now) = 0;
  /// Deletes the tickets with expires_ms <= `now`, claimed or not; how many.
  virtual DbResult<std::int64_t> delete_expired_tickets(UnixMillis now) = 0;
};

/// store.transaction(work) for a `work` that returns a DbResult<T> or a DbStatus: its own
/// result when it ran and the commit succeeded, otherwise the error that stopped it.
template <class Work>
std::invoke_result_t<Work&> atomically(Store& store, Work work) {
  std::optional<std::invoke_result_t<Work&>> result;
  const DbStatus status = store.transaction([&]() -> DbStatus {
    result.emplace(work());
    if (!result->ok()) return result->error();
    return {};
  });
  if (!status.ok()) return status.error();
  return std::move(*result);
}

struct SqliteOptions {
  std::string path;            ///< the database file; created with its directory's permissions
  int busy_timeout_ms = 5000;  ///< wait this long for another process's lock, then Busy
  /// NORMAL in WAL mode: a commit survives a crash or kill -9 of this process (the WAL is in the
  /// OS's page cache), and the file is never corrupted; only a power loss or OS crash can lose
  /// the last commits. FULL also fsyncs every commit, at several ms each. See db/README.md.
  bool synchronous_full = false;
};

/// Opens (creating if needed) and migrates a SQLite database. CannotOpen, CorruptDatabase or
/// SchemaTooNew with the file's path in the message when it cannot be used.
DbResult<std::unique_ptr<Store>> open_sqlite_store(const SqliteOptions& options);

/// The schema version this binary writes (PRAGMA user_version after migrating).
int sqlite_schema_version();

struct PostgresOptions {
  /// A libpq connection string or URL: "postgresql://user:password@host:port/dbname?…". Error
  /// messages name it without its password.
  std::string url;
  /// Wait this long for another server's write lock (Store::transaction), then Busy. At least 1.
  int busy_timeout_ms = 5000;
  int connect_timeout_s = 5;  ///< unless the URL sets connect_timeout
};

/// Connects to a PostgreSQL database and migrates it (the same numbered schema as SQLite's).
/// Unavailable when the server cannot be reached (retry later); CannotOpen when it refuses the
/// login or the database does not exist; SchemaTooNew when a newer Ricochet migrated it. A
/// connection lost later is re-opened at the next call outside a transaction; the call that met
/// the loss fails with Unavailable.
DbResult<std::unique_ptr<Store>> open_postgres_store(const PostgresOptions& options);

/// The schema version this binary writes to PostgreSQL: the same number as SQLite's.
int postgres_schema_version();

/// Where a server keeps its data: a PostgreSQL URL or a SQLite file.
struct StoreOptions {
  /// "postgresql://…" or "postgres://…" selects PostgreSQL; anything else is a SQLite file path.
  std::string url_or_path;
  int busy_timeout_ms = 5000;  ///< SqliteOptions / PostgresOptions::busy_timeout_ms
};

/// Whether `url_or_path` names a PostgreSQL database rather than a SQLite file.
bool is_postgres_url(std::string_view url_or_path);

/// open_postgres_store or open_sqlite_store, by the form of `url_or_path`.
DbResult<std::unique_ptr<Store>> open_store(const StoreOptions& options);

}  // namespace ricochet::db
