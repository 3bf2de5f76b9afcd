#pragma once
/// The persistence interface: what the server needs from a database, and nothing about how.
///
/// SQLite (open_sqlite_store) is the embedded default: one file, no server. A backend for
/// operators running many server processes (PostgreSQL) implements the same interface. Every
/// call is synchronous and may block on the disk: the game thread never calls a Store directly,
/// it goes through DbWorker (db_worker.h). One Store is used by one thread at a time.
///
/// The store validates what it must keep consistent (foreign keys, uniqueness, one transaction
/// per match); the account rules (name syntax, password hashing, sessions, rate limits) live
/// above it in Accounts (accounts.h), the same for every backend.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "ricochet/db/records.h"
#include "ricochet/db/result.h"

namespace ricochet::db {

class Store {
 public:
  virtual ~Store() = default;

  /// Runs `work` as one unit: the store calls it makes are committed together when it succeeds,
  /// and none of them is when it fails (or the commit does). The write lock is taken before
  /// `work` starts (SQLite: BEGIN IMMEDIATE), so what it reads cannot change under it and it
  /// never fails half-way for another writer's lock. A transaction inside `work` joins this one.
  /// Busy when the lock is not had within the busy timeout.
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

  // --- matches, stats, leaderboards ---
  /// Writes the match, every player's result, their lifetime stats and new ratings (rating.h)
  /// in one transaction: after a crash either all of it is there or none. InvalidMatch when a
  /// player is listed twice or unknown.
  virtual DbResult<MatchId> record_match(const MatchRecord& match) = 0;
  virtual DbResult<std::int64_t> match_count() = 0;
  /// Zeros and the initial rating for an account that never played; UnknownAccount if none.
  virtual DbResult<PlayerStats> player_stats(AccountId id) = 0;
  /// The first `limit` entries, best first (ties by account id). WinRate lists only accounts
  /// with at least `min_matches` matches.
  virtual DbResult<std::vector<LeaderboardEntry>> leaderboard(LeaderboardKind kind, int limit,
                                                              std::int64_t min_matches) = 0;
  /// The account's entry on that board (rank 1 is best); nullopt when it is not on it (no
  /// matches, or too few for WinRate).
  virtual DbResult<std::optional<LeaderboardEntry>> rank_of(AccountId id, LeaderboardKind kind,
                                                            std::int64_t min_matches) = 0;
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
  /// the last commits. FULL also fsyncs every commit, at several ms each. See README.
  bool synchronous_full = false;
};

/// Opens (creating if needed) and migrates a SQLite database. CannotOpen, CorruptDatabase or
/// SchemaTooNew with the file's path in the message when it cannot be used.
DbResult<std::unique_ptr<Store>> open_sqlite_store(const SqliteOptions& options);

/// The schema version this binary writes (PRAGMA user_version after migrating).
int sqlite_schema_version();

}  // namespace ricochet::db
