/// The PostgreSQL Store (store.h): one libpq connection, every statement prepared once per
/// connection and run with bound parameters (no SQL is ever built from values).
///
/// Opening, in order: connect (Unavailable when the server cannot be reached, CannotOpen when it
/// refuses us) → lock_timeout from busy_timeout_ms → read the schema version, refusing a newer
/// one before anything is written (SchemaTooNew) → migrations → prepare the statements.
///
/// A lost connection (the server restarted, a network cut) fails the call that met it with
/// Unavailable; the next call outside a transaction reconnects, sets lock_timeout and prepares
/// the statements again, or answers Unavailable while the server is still away.

#include <algorithm>
#include <array>
#include <utility>

#include "leaderboard_sql.h"
#include "postgres_handle.h"
#include "postgres_migrations.h"
#include "ricochet/db/store.h"

namespace ricochet::db {

namespace {

constexpr std::size_t kTokenHashBytes = 32;  ///< SHA-256

constexpr std::array kBoards = {LeaderboardKind::Rating, LeaderboardKind::Kills,
                                LeaderboardKind::WinRate};

/// The prepared statements, by the name they are prepared under.
enum class Sql {
  InsertAccount,
  FindAccountByKey,
  Account,
  SetPasswordHash,
  SetBanned,
  SetLastLogin,
  InsertSession,
  FindSession,
  DeleteSession,
  DeleteSessionsOf,
  DeleteExpiredSessions,
  InsertLoginFailure,
  CountLoginFailures,
  DeleteLoginFailure,
  DeleteLoginFailuresOf,
  DeleteLoginFailuresUntil,
  RatingOf,
  InsertMatch,
  InsertMatchPlayer,
  UpsertStats,
  FindMatch,
  MatchCount,
  PlayerStats,
  // fleet directory and tickets
  UpsertGameServer,
  DeleteServerMatches,
  InsertServerMatch,
  GameServers,
  DirectoryMatches,
  DeleteServerTickets,
  DeleteGameServer,
  DeleteStaleTickets,
  DeleteStaleServers,
  InsertTicket,
  FindTicket,
  HeldSeats,
  DeleteUnclaimedTicketsOf,
  ClaimTicket,
  DeleteExpiredTickets,
  Top,  ///< then EntryOf and CountBetter, one per board each (board_statement)
};
constexpr int kFixedStatements = static_cast<int>(Sql::Top);

constexpr std::array<const char*, kFixedStatements> kSql = {
    "INSERT INTO accounts (username, username_key, password_hash, created_ms)"
    " VALUES ($1, $2, $3, $4) RETURNING id",
    "SELECT id, username, created_ms, last_login_ms, banned, password_hash"
    " FROM accounts WHERE username_key = $1",
    "SELECT id, username, created_ms, last_login_ms, banned FROM accounts WHERE id = $1",
    "UPDATE accounts SET password_hash = $1 WHERE id = $2",
    "UPDATE accounts SET banned = $1 WHERE id = $2",
    "UPDATE accounts SET last_login_ms = $1 WHERE id = $2",
    "INSERT INTO sessions (token_hash, account_id, created_ms, expires_ms)"
    " VALUES ($1, $2, $3, $4)",
    "SELECT account_id, created_ms, expires_ms FROM sessions WHERE token_hash = $1",
    "DELETE FROM sessions WHERE token_hash = $1",
    "DELETE FROM sessions WHERE account_id = $1",
    "DELETE FROM sessions WHERE expires_ms < $1",
    "INSERT INTO login_failures (key, at_ms) VALUES ($1, $2) RETURNING id",
    "SELECT COUNT(*) FROM login_failures WHERE key = $1 AND at_ms > $2",
    "DELETE FROM login_failures WHERE id = $1",
    "DELETE FROM login_failures WHERE key = $1",
    "DELETE FROM login_failures WHERE at_ms <= $1",
    "SELECT s.rating FROM accounts AS a LEFT JOIN player_stats AS s ON s.account_id = a.id"
    " WHERE a.id = $1",
    "INSERT INTO matches (map, mode, started_ms, ended_ms, tick_rate, aborted, red_score,"
    " blue_score, uuid) VALUES ($1, $2, $3, $4, $5, $6, $7, $8, NULLIF($9, '')) RETURNING id",
    "INSERT INTO match_players (match_id, account_id, kills, deaths, score, shots, hits,"
    " damage_dealt, damage_taken, seconds_played, rating_before, rating_after, team)"
    " VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9, $10, $11, $12, $13)",
    "INSERT INTO player_stats AS s (account_id, matches, wins, kills, deaths, score, shots, hits,"
    " damage_dealt, damage_taken, seconds_played, rating)"
    " VALUES ($1, 1, $2, $3, $4, $5, $6, $7, $8, $9, $10, $11)"
    " ON CONFLICT (account_id) DO UPDATE SET matches = s.matches + 1,"
    " wins = s.wins + excluded.wins, kills = s.kills + excluded.kills,"
    " deaths = s.deaths + excluded.deaths, score = s.score + excluded.score,"
    " shots = s.shots + excluded.shots, hits = s.hits + excluded.hits,"
    " damage_dealt = s.damage_dealt + excluded.damage_dealt,"
    " damage_taken = s.damage_taken + excluded.damage_taken,"
    " seconds_played = s.seconds_played + excluded.seconds_played,"
    " rating = excluded.rating",
    "SELECT m.id, p.account_id, p.rating_before, p.rating_after FROM matches AS m"
    " JOIN match_players AS p ON p.match_id = m.id WHERE m.uuid = $1",
    "SELECT COUNT(*) FROM matches",
    "SELECT a.username, s.account_id IS NOT NULL, s.matches, s.wins, s.kills, s.deaths,"
    " s.score, s.shots, s.hits, s.damage_dealt, s.damage_taken, s.seconds_played, s.rating"
    " FROM accounts AS a LEFT JOIN player_stats AS s ON s.account_id = a.id"
    " WHERE a.id = $1",
    // fleet directory and tickets
    "INSERT INTO game_servers (server_id, host, control_port, game_port, certificate_sha256,"
    " version, capacity, players, heartbeat_ms, started_ms, counted_ms, admin_port)"
    " VALUES ($1, $2, $3, $4, $5, $6, $7, $8, $9, $10, $11, $12)"
    " ON CONFLICT (server_id) DO UPDATE SET host = excluded.host,"
    " control_port = excluded.control_port, game_port = excluded.game_port,"
    " certificate_sha256 = excluded.certificate_sha256, version = excluded.version,"
    " capacity = excluded.capacity, players = excluded.players,"
    " heartbeat_ms = excluded.heartbeat_ms, started_ms = excluded.started_ms,"
    " counted_ms = excluded.counted_ms, admin_port = excluded.admin_port",
    "DELETE FROM game_server_matches WHERE server_id = $1",
    "INSERT INTO game_server_matches (server_id, match_id, mode, map, players, capacity, open)"
    " VALUES ($1, $2, $3, $4, $5, $6, $7)",
    "SELECT server_id, host, control_port, game_port, certificate_sha256, version, capacity,"
    " players, heartbeat_ms, started_ms, counted_ms, admin_port FROM game_servers WHERE "
    "heartbeat_ms > $1"
    " ORDER BY server_id",
    "SELECT m.server_id, m.match_id, m.mode, m.map, m.players, m.capacity, m.open"
    " FROM game_server_matches AS m JOIN game_servers AS s ON s.server_id = m.server_id"
    " WHERE s.heartbeat_ms > $1 ORDER BY m.server_id, m.match_id",
    "DELETE FROM tickets WHERE server_id = $1 AND claimed_ms IS NULL",
    "DELETE FROM game_servers WHERE server_id = $1",
    "DELETE FROM tickets WHERE server_id IN"
    " (SELECT server_id FROM game_servers WHERE heartbeat_ms <= $1)",
    "DELETE FROM game_servers WHERE heartbeat_ms <= $1",
    "INSERT INTO tickets (token_hash, account_id, server_id, match_id, mode, map, created_ms,"
    " expires_ms) VALUES ($1, $2, $3, $4, $5, $6, $7, $8)",
    "SELECT account_id, server_id, match_id, mode, map, created_ms, expires_ms, claimed_ms"
    " FROM tickets WHERE token_hash = $1",
    "SELECT t.server_id, t.match_id, COUNT(*), COUNT(t.claimed_ms) FROM tickets AS t"
    " JOIN game_servers AS s ON s.server_id = t.server_id"
    " WHERE (t.claimed_ms IS NULL AND t.expires_ms > $1) OR t.claimed_ms >= s.counted_ms"
    " GROUP BY t.server_id, t.match_id ORDER BY t.server_id, t.match_id",
    "DELETE FROM tickets WHERE account_id = $1 AND claimed_ms IS NULL",
    "UPDATE tickets SET claimed_ms = $4 WHERE token_hash = $1 AND claimed_ms IS NULL"
    " AND server_id = $2 AND account_id = $3 AND expires_ms > $4"
    " RETURNING match_id, mode, map",
    "DELETE FROM tickets WHERE expires_ms <= $1",
};

enum class BoardQuery { Top, EntryOf, CountBetter };

/// The name a statement is prepared under: "r0", "r1", …
std::string statement_name(int index) {
  return "r" + std::to_string(index);
}
std::string statement_name(Sql sql) {
  return statement_name(static_cast<int>(sql));
}
std::string board_statement(BoardQuery query, LeaderboardKind kind) {
  return statement_name(kFixedStatements + static_cast<int>(query) * int(kBoards.size()) +
                        static_cast<int>(kind));
}

class PostgresStore final : public Store {
 public:
  PostgresStore(PostgresOptions options, std::string where, postgres::Connection conn)
      : options_(std::move(options)), where_(std::move(where)), conn_(std::move(conn)) {}

  /// lock_timeout and the prepared statements, on a new or re-opened connection.
  DbStatus set_up_connection();

  DbStatus transaction(const std::function<DbStatus()>& work) override;
  DbResult<AccountId> insert_account(std::string_view username, std::string_view username_key,
                                     std::string_view password_hash, UnixMillis now) override;
  DbResult<std::optional<AccountCredentials>> find_account_by_key(
      std::string_view username_key) override;
  DbResult<Account> account(AccountId id) override;
  DbStatus set_password_hash(AccountId id, std::string_view password_hash) override;
  DbStatus set_banned(AccountId id, bool banned) override;
  DbStatus set_last_login(AccountId id, UnixMillis now) override;

  DbStatus insert_session(std::string_view token_hash, AccountId account, UnixMillis created_ms,
                          UnixMillis expires_ms) override;
  DbResult<std::optional<SessionRow>> find_session(std::string_view token_hash) override;
  DbStatus delete_session(std::string_view token_hash) override;
  DbStatus delete_sessions_of(AccountId account) override;
  DbResult<std::int64_t> delete_expired_sessions(UnixMillis now) override;

  DbResult<std::int64_t> insert_login_failure(std::string_view key, UnixMillis at_ms) override;
  DbResult<std::int64_t> count_login_failures(std::string_view key, UnixMillis after_ms) override;
  DbStatus delete_login_failure(std::int64_t id) override;
  DbStatus delete_login_failures_of(std::string_view key) override;
  DbStatus delete_login_failures_until(UnixMillis at_ms) override;

  DbResult<std::optional<double>> rating_of(AccountId id) override;
  DbResult<MatchId> insert_match(const MatchRecord& match,
                                 const std::vector<PlayerOutcome>& outcomes) override;
  DbResult<std::optional<StoredMatch>> find_match(std::string_view uuid) override;
  DbResult<std::int64_t> match_count() override;
  DbResult<PlayerStats> player_stats(AccountId id) override;
  DbResult<std::vector<LeaderboardEntry>> leaderboard(LeaderboardKind kind, int limit,
                                                      std::int64_t min_matches) override;
  DbResult<std::optional<LeaderboardEntry>> board_entry(AccountId id,
                                                        LeaderboardKind kind) override;
  DbResult<std::int64_t> count_better(LeaderboardKind kind, double value,
                                      std::int64_t min_matches) override;

  DbStatus upsert_game_server(const GameServerRow& server) override;
  DbStatus replace_game_server_matches(std::string_view server_id,
                                       const std::vector<HostedMatch>& matches) override;
  DbResult<std::vector<GameServerRow>> game_servers(UnixMillis heartbeat_after_ms) override;
  DbResult<std::vector<DirectoryMatch>> directory_matches(UnixMillis heartbeat_after_ms) override;
  DbResult<bool> delete_game_server(std::string_view server_id) override;
  DbResult<std::int64_t> delete_game_servers_until(UnixMillis heartbeat_until_ms) override;
  DbStatus insert_ticket(const TicketRow& ticket) override;
  DbResult<std::optional<TicketRow>> find_ticket(std::string_view token_hash) override;
  DbResult<std::vector<HeldSeats>> held_seats(UnixMillis now) override;
  DbResult<std::int64_t> delete_unclaimed_tickets_of(AccountId account) override;
  DbResult<std::optional<ClaimedTicket>> claim_ticket(std::string_view token_hash,
                                                      std::string_view server_id, AccountId account,
                                                      UnixMillis now) override;
  DbResult<std::int64_t> delete_expired_tickets(UnixMillis now) override;

 private:
  /// Re-opens a lost connection, outside a transaction only (one that lost its connection has
  /// already failed). Unavailable while the server is away.
  DbStatus reconnect_if_lost();
  /// Runs a prepared statement. The result, or the error with `what` in its message.
  DbResult<postgres::Result> run(const std::string& name, const postgres::Params& params,
                                 std::string_view what);
  DbResult<postgres::Result> run(Sql sql, const postgres::Params& params, std::string_view what) {
    return run(statement_name(sql), params, what);
  }
  /// Runs a statement that returns nothing.
  DbStatus execute(Sql sql, const postgres::Params& params, std::string_view what) {
    auto r = run(sql, params, what);
    if (!r.ok()) return r.error();
    return {};
  }
  DbError failure(const postgres::Result& result, std::string_view what) const {
    return postgres::error_from(conn_.get(), result, where_, what);
  }
  DbError bad_row(const postgres::Result& result, std::string_view what) const {
    return DbError{DbErrorCode::CorruptDatabase,
                   where_ + ": " + std::string(what) + ": " + result.column_error()};
  }
  DbError unknown_account(AccountId id) const {
    return DbError{DbErrorCode::UnknownAccount, "no account with id " + std::to_string(id)};
  }
  /// Runs an UPDATE of one account by id; UnknownAccount when no row changed.
  DbStatus update_account(Sql sql, postgres::Params params, AccountId id, std::string_view what);
  DbResult<MatchId> write_match(const MatchRecord& match,
                                const std::vector<PlayerOutcome>& outcomes);

  PostgresOptions options_;
  std::string where_;            ///< the URL without its password, for messages
  bool in_transaction_ = false;  ///< inside transaction(): a nested one joins it
  postgres::Connection conn_;
};

/// The write lock's busy timeout, for the session. 0 would mean "wait forever" to PostgreSQL.
DbStatus set_lock_timeout(PGconn* conn, int busy_timeout_ms, const std::string& where) {
  const std::string sql = "SET lock_timeout = " + std::to_string(std::max(1, busy_timeout_ms));
  if (postgres::Result r = postgres::exec(conn, sql.c_str()); !r.ok())
    return postgres::error_from(conn, r, where, "setting lock_timeout");
  return {};
}

DbStatus PostgresStore::set_up_connection() {
  if (DbStatus s = set_lock_timeout(conn_.get(), options_.busy_timeout_ms, where_); !s) return s;
  auto prepare = [&](const std::string& name, const char* sql) -> DbStatus {
    postgres::Result r(PQprepare(conn_.get(), name.c_str(), sql, 0, nullptr));
    if (!r.ok()) return failure(r, std::string("preparing \"") + sql + "\"");
    return {};
  };
  for (int i = 0; i < kFixedStatements; ++i)
    if (DbStatus s = prepare(statement_name(i), kSql[static_cast<std::size_t>(i)]); !s) return s;
  for (LeaderboardKind kind : kBoards) {
    for (const auto& [query, sql] :
         {std::pair{BoardQuery::Top, leaderboard_sql::postgres_top(kind)},
          std::pair{BoardQuery::EntryOf, leaderboard_sql::postgres_entry_of(kind)},
          std::pair{BoardQuery::CountBetter, leaderboard_sql::postgres_count_better(kind)}})
      if (DbStatus s = prepare(board_statement(query, kind), sql); !s) return s;
  }
  return {};
}

DbStatus PostgresStore::reconnect_if_lost() {
  if (in_transaction_ || PQstatus(conn_.get()) == CONNECTION_OK) return {};
  PQreset(conn_.get());
  if (PQstatus(conn_.get()) != CONNECTION_OK)
    return DbError{DbErrorCode::Unavailable,
                   where_ + ": reconnecting failed: " + PQerrorMessage(conn_.get()) +
                       "; the database server is unreachable, retry later"};
  return set_up_connection();
}

DbResult<postgres::Result> PostgresStore::run(const std::string& name,
                                              const postgres::Params& params,
                                              std::string_view what) {
  if (!params.problem().empty())
    return DbError{DbErrorCode::Storage, where_ + ": " + std::string(what) + ": " +
                                             params.problem() + " cannot be stored"};
  if (DbStatus s = reconnect_if_lost(); !s) return s.error();
  postgres::Result r(params.exec(conn_.get(), name.c_str()));
  if (!r.ok()) return failure(r, what);
  return r;
}

// --- transactions ---

// The write lock. SQLite's BEGIN IMMEDIATE takes the database's one write lock before `work`
// runs; a transaction-scoped advisory lock right after BEGIN is PostgreSQL's plain equivalent:
// every writing transaction of every server process takes the same lock, so they run one at a
// time, each sees the commits of those before it (READ COMMITTED, see postgres_handle.h), and
// none fails half-way on a serialization error or deadlock. Rating updates (read, compute,
// write) therefore cannot be lost. What it costs: one more round trip per transaction, and
// writes across all servers are serialised on one lock, as on SQLite (reads are not: they take
// no lock). Row locks (SELECT … FOR UPDATE per player) would let disjoint matches commit in
// parallel, at the price of ordering locks and retrying deadlocks; match results are too rare
// to need it.
DbStatus PostgresStore::transaction(const std::function<DbStatus()>& work) {
  if (in_transaction_) return work();
  if (DbStatus s = reconnect_if_lost(); !s) return s;
  postgres::Transaction transaction(conn_.get());
  if (postgres::Result r = transaction.begin(); r.get()) return failure(r, "taking the write lock");
  struct Inside {
    bool& flag;
    ~Inside() { flag = false; }
  };
  in_transaction_ = true;
  const Inside inside{in_transaction_};
  const DbStatus status = work();
  if (!status.ok()) return status;  // rolled back by ~Transaction
  if (postgres::Result r = transaction.commit(); r.get())
    return failure(r, "committing a transaction");
  return {};
}

// --- accounts ---

DbResult<AccountId> PostgresStore::insert_account(std::string_view username,
                                                  std::string_view username_key,
                                                  std::string_view password_hash, UnixMillis now) {
  postgres::Params p;
  p.text(username).text(username_key).text(password_hash).integer(now);
  auto r = run(Sql::InsertAccount, p, "inserting an account");
  if (!r.ok() && r.error().code == DbErrorCode::Storage &&
      r.error().message.find("accounts_username_key_key") != std::string::npos)
    return DbError{DbErrorCode::DuplicateUsername,
                   "username '" + std::string(username) + "' is taken (ignoring case)"};
  if (!r.ok()) return r.error();
  const AccountId id = r.value().integer(0, 0);
  if (!r.value().column_error().empty()) return bad_row(r.value(), "inserting an account");
  return id;
}

DbResult<std::optional<AccountCredentials>> PostgresStore::find_account_by_key(
    std::string_view username_key) {
  postgres::Params p;
  p.text(username_key);
  auto r = run(Sql::FindAccountByKey, p, "finding an account by name");
  if (!r.ok()) return r.error();
  postgres::Result& q = r.value();
  if (q.rows() == 0) return std::optional<AccountCredentials>();
  AccountCredentials found;
  found.account.id = q.integer(0, 0);
  found.account.username = q.text(0, 1);
  found.account.created_ms = q.integer(0, 2);
  found.account.last_login_ms = q.optional_integer(0, 3);
  found.account.banned = q.integer(0, 4) != 0;
  found.password_hash = q.text(0, 5);
  if (!q.column_error().empty()) return bad_row(q, "reading an account");
  return std::optional<AccountCredentials>(std::move(found));
}

DbResult<Account> PostgresStore::account(AccountId id) {
  postgres::Params p;
  p.integer(id);
  auto r = run(Sql::Account, p, "reading an account");
  if (!r.ok()) return r.error();
  postgres::Result& q = r.value();
  if (q.rows() == 0) return unknown_account(id);
  Account found;
  found.id = q.integer(0, 0);
  found.username = q.text(0, 1);
  found.created_ms = q.integer(0, 2);
  found.last_login_ms = q.optional_integer(0, 3);
  found.banned = q.integer(0, 4) != 0;
  if (!q.column_error().empty()) return bad_row(q, "reading an account");
  return found;
}

DbStatus PostgresStore::update_account(Sql sql, postgres::Params params, AccountId id,
                                       std::string_view what) {
  params.integer(id);
  auto r = run(sql, params, what);
  if (!r.ok()) return r.error();
  if (r.value().changed() == 0) return unknown_account(id);
  return {};
}

DbStatus PostgresStore::set_password_hash(AccountId id, std::string_view password_hash) {
  postgres::Params p;
  p.text(password_hash);
  return update_account(Sql::SetPasswordHash, std::move(p), id, "setting a password hash");
}

DbStatus PostgresStore::set_banned(AccountId id, bool banned) {
  postgres::Params p;
  p.integer(banned ? 1 : 0);
  return update_account(Sql::SetBanned, std::move(p), id, "setting the banned flag");
}

DbStatus PostgresStore::set_last_login(AccountId id, UnixMillis now) {
  postgres::Params p;
  p.integer(now);
  return update_account(Sql::SetLastLogin, std::move(p), id, "setting the last login time");
}

// --- sessions ---

/// UnknownSession for a hash of the wrong size: the caller passes SHA-256 digests only.
DbStatus check_token_hash(std::string_view token_hash) {
  if (token_hash.size() == kTokenHashBytes) return {};
  return DbError{DbErrorCode::UnknownSession, "a session token hash is " +
                                                  std::to_string(kTokenHashBytes) + " bytes, got " +
                                                  std::to_string(token_hash.size())};
}

DbStatus PostgresStore::insert_session(std::string_view token_hash, AccountId account,
                                       UnixMillis created_ms, UnixMillis expires_ms) {
  if (DbStatus s = check_token_hash(token_hash); !s) return s;
  postgres::Params p;
  p.bytes(token_hash).integer(account).integer(created_ms).integer(expires_ms);
  auto r = run(Sql::InsertSession, p, "inserting a session");
  if (!r.ok() && r.error().message.find("sessions_account_id_fkey") != std::string::npos)
    return unknown_account(account);
  if (!r.ok()) return r.error();
  return {};
}

DbResult<std::optional<SessionRow>> PostgresStore::find_session(std::string_view token_hash) {
  if (token_hash.size() != kTokenHashBytes) return std::optional<SessionRow>();
  postgres::Params p;
  p.bytes(token_hash);
  auto r = run(Sql::FindSession, p, "finding a session");
  if (!r.ok()) return r.error();
  postgres::Result& q = r.value();
  if (q.rows() == 0) return std::optional<SessionRow>();
  SessionRow row;
  row.account = q.integer(0, 0);
  row.created_ms = q.integer(0, 1);
  row.expires_ms = q.integer(0, 2);
  if (!q.column_error().empty()) return bad_row(q, "reading a session");
  return std::optional<SessionRow>(row);
}

DbStatus PostgresStore::delete_session(std::string_view token_hash) {
  if (token_hash.size() != kTokenHashBytes) return {};  // no such session can exist
  postgres::Params p;
  p.bytes(token_hash);
  return execute(Sql::DeleteSession, p, "deleting a session");
}

DbStatus PostgresStore::delete_sessions_of(AccountId account) {
  postgres::Params p;
  p.integer(account);
  return execute(Sql::DeleteSessionsOf, p, "deleting the sessions of an account");
}

DbResult<std::int64_t> PostgresStore::delete_expired_sessions(UnixMillis now) {
  postgres::Params p;
  p.integer(now);
  auto r = run(Sql::DeleteExpiredSessions, p, "deleting expired sessions");
  if (!r.ok()) return r.error();
  return r.value().changed();
}

// --- failed logins ---

DbResult<std::int64_t> PostgresStore::insert_login_failure(std::string_view key, UnixMillis at_ms) {
  postgres::Params p;
  p.text(key).integer(at_ms);
  auto r = run(Sql::InsertLoginFailure, p, "noting a failed login");
  if (!r.ok()) return r.error();
  const std::int64_t id = r.value().integer(0, 0);
  if (!r.value().column_error().empty()) return bad_row(r.value(), "noting a failed login");
  return id;
}

DbResult<std::int64_t> PostgresStore::count_login_failures(std::string_view key,
                                                           UnixMillis after_ms) {
  postgres::Params p;
  p.text(key).integer(after_ms);
  auto r = run(Sql::CountLoginFailures, p, "counting failed logins");
  if (!r.ok()) return r.error();
  const std::int64_t count = r.value().integer(0, 0);
  if (!r.value().column_error().empty()) return bad_row(r.value(), "counting failed logins");
  return count;
}

DbStatus PostgresStore::delete_login_failure(std::int64_t id) {
  postgres::Params p;
  p.integer(id);
  return execute(Sql::DeleteLoginFailure, p, "forgetting a failed login");
}

DbStatus PostgresStore::delete_login_failures_of(std::string_view key) {
  postgres::Params p;
  p.text(key);
  return execute(Sql::DeleteLoginFailuresOf, p, "forgetting the failed logins of a key");
}

DbStatus PostgresStore::delete_login_failures_until(UnixMillis at_ms) {
  postgres::Params p;
  p.integer(at_ms);
  return execute(Sql::DeleteLoginFailuresUntil, p, "dropping old failed logins");
}

// --- matches and stats ---

DbResult<std::optional<double>> PostgresStore::rating_of(AccountId id) {
  postgres::Params p;
  p.integer(id);
  auto r = run(Sql::RatingOf, p, "reading a player's rating");
  if (!r.ok()) return r.error();
  postgres::Result& q = r.value();
  if (q.rows() == 0) return unknown_account(id);
  std::optional<double> rating;
  if (!q.is_null(0, 0)) rating = q.real(0, 0);
  if (!q.column_error().empty()) return bad_row(q, "reading a player's rating");
  return rating;
}

DbResult<MatchId> PostgresStore::write_match(const MatchRecord& match,
                                             const std::vector<PlayerOutcome>& outcomes) {
  postgres::Params m;
  m.text(match.map).text(match.mode).integer(match.started_ms).integer(match.ended_ms);
  m.integer(match.tick_rate).integer(match.aborted ? 1 : 0);
  m.integer(match.team_scores.red).integer(match.team_scores.blue).text(match.uuid);
  auto inserted = run(Sql::InsertMatch, m, "inserting a match");
  if (!inserted.ok()) return inserted.error();
  const MatchId id = inserted.value().integer(0, 0);
  if (!inserted.value().column_error().empty())
    return bad_row(inserted.value(), "inserting a match");
  for (std::size_t i = 0; i < match.players.size(); ++i) {
    const PlayerResult& pr = match.players[i];
    postgres::Params p;
    p.integer(id).integer(pr.account).integer(pr.kills).integer(pr.deaths).integer(pr.score);
    p.integer(pr.shots).integer(pr.hits).real(pr.damage_dealt).real(pr.damage_taken);
    p.real(pr.seconds_played).real(outcomes[i].rating_before);
    p.real(outcomes[i].rating_after).integer(pr.team);
    if (DbStatus s = execute(Sql::InsertMatchPlayer, p, "inserting a match player"); !s)
      return s.error();
  }
  for (std::size_t i = 0; i < match.players.size(); ++i) {
    const PlayerResult& pr = match.players[i];
    postgres::Params p;
    p.integer(pr.account).integer(outcomes[i].won ? 1 : 0).integer(pr.kills);
    p.integer(pr.deaths).integer(pr.score).integer(pr.shots).integer(pr.hits);
    p.real(pr.damage_dealt).real(pr.damage_taken).real(pr.seconds_played);
    p.real(outcomes[i].rating_after);
    if (DbStatus s = execute(Sql::UpsertStats, p, "updating a player's stats"); !s)
      return s.error();
  }
  return id;
}

DbResult<MatchId> PostgresStore::insert_match(const MatchRecord& match,
                                              const std::vector<PlayerOutcome>& outcomes) {
  if (outcomes.size() != match.players.size()) {
    return DbError{DbErrorCode::InvalidMatch, "a match of " + std::to_string(match.players.size()) +
                                                  " players needs as many outcomes, got " +
                                                  std::to_string(outcomes.size())};
  }
  return atomically(*this, [&] { return write_match(match, outcomes); });
}

DbResult<std::optional<StoredMatch>> PostgresStore::find_match(std::string_view uuid) {
  postgres::Params p;
  p.text(uuid);
  auto r = run(Sql::FindMatch, p, "finding a match by its uuid");
  if (!r.ok()) return r.error();
  postgres::Result& q = r.value();
  std::optional<StoredMatch> found;
  for (int row = 0; row < q.rows(); ++row) {
    if (!found) found.emplace().id = q.integer(row, 0);
    found->accounts.push_back(q.integer(row, 1));
    found->outcomes.push_back({q.real(row, 2), q.real(row, 3), false});
  }
  if (!q.column_error().empty()) return bad_row(q, "finding a match by its uuid");
  return found;
}

DbResult<std::int64_t> PostgresStore::match_count() {
  auto r = run(Sql::MatchCount, {}, "counting matches");
  if (!r.ok()) return r.error();
  const std::int64_t count = r.value().integer(0, 0);
  if (!r.value().column_error().empty()) return bad_row(r.value(), "counting matches");
  return count;
}

DbResult<PlayerStats> PostgresStore::player_stats(AccountId id) {
  postgres::Params p;
  p.integer(id);
  auto r = run(Sql::PlayerStats, p, "reading player stats");
  if (!r.ok()) return r.error();
  postgres::Result& q = r.value();
  if (q.rows() == 0) return unknown_account(id);
  PlayerStats stats;
  stats.account = id;
  stats.username = q.text(0, 0);
  if (q.text(0, 1) == "t") {  // has a stats row
    stats.matches = q.integer(0, 2);
    stats.wins = q.integer(0, 3);
    stats.kills = q.integer(0, 4);
    stats.deaths = q.integer(0, 5);
    stats.score = q.integer(0, 6);
    stats.shots = q.integer(0, 7);
    stats.hits = q.integer(0, 8);
    stats.damage_dealt = q.real(0, 9);
    stats.damage_taken = q.real(0, 10);
    stats.seconds_played = q.real(0, 11);
    stats.rating = q.real(0, 12);
  }
  if (!q.column_error().empty()) return bad_row(q, "reading player stats");
  return stats;
}

// --- leaderboards ---

/// Reads a board value: kills are integers, rating and win rate reals.
double board_value(postgres::Result& q, int row, int column, LeaderboardKind kind) {
  return kind == LeaderboardKind::Kills ? static_cast<double>(q.integer(row, column))
                                        : q.real(row, column);
}

DbResult<std::vector<LeaderboardEntry>> PostgresStore::leaderboard(LeaderboardKind kind, int limit,
                                                                   std::int64_t min_matches) {
  std::vector<LeaderboardEntry> entries;
  if (limit <= 0) return entries;
  postgres::Params p;
  p.integer(limit);
  if (kind == LeaderboardKind::WinRate) p.integer(min_matches);
  auto r = run(board_statement(BoardQuery::Top, kind), p, "reading a leaderboard");
  if (!r.ok()) return r.error();
  postgres::Result& q = r.value();
  for (int row = 0; row < q.rows(); ++row) {
    LeaderboardEntry e;
    e.account = q.integer(row, 0);
    e.username = q.text(row, 1);
    e.value = board_value(q, row, 2, kind);
    e.matches = q.integer(row, 3);
    entries.push_back(std::move(e));
  }
  if (!q.column_error().empty()) return bad_row(q, "reading a leaderboard");
  return entries;
}

DbResult<std::optional<LeaderboardEntry>> PostgresStore::board_entry(AccountId id,
                                                                     LeaderboardKind kind) {
  postgres::Params p;
  p.integer(id);
  auto r = run(board_statement(BoardQuery::EntryOf, kind), p, "reading a leaderboard entry");
  if (!r.ok()) return r.error();
  postgres::Result& q = r.value();
  if (q.rows() == 0) return unknown_account(id);
  if (q.is_null(0, 1)) return std::optional<LeaderboardEntry>();  // never played
  LeaderboardEntry e;
  e.account = id;
  e.username = q.text(0, 0);
  e.matches = q.integer(0, 1);
  e.value = board_value(q, 0, 2, kind);
  if (!q.column_error().empty()) return bad_row(q, "reading a leaderboard entry");
  return std::optional<LeaderboardEntry>(std::move(e));
}

DbResult<std::int64_t> PostgresStore::count_better(LeaderboardKind kind, double value,
                                                   std::int64_t min_matches) {
  postgres::Params p;
  if (kind == LeaderboardKind::Kills)
    p.integer(static_cast<std::int64_t>(value));
  else
    p.real(value);
  if (kind == LeaderboardKind::WinRate) p.integer(min_matches);
  auto r = run(board_statement(BoardQuery::CountBetter, kind), p, "ranking an account");
  if (!r.ok()) return r.error();
  const std::int64_t better = r.value().integer(0, 0);
  if (!r.value().column_error().empty()) return bad_row(r.value(), "ranking an account");
  return better;
}

// --- fleet directory and tickets ---

DbStatus PostgresStore::upsert_game_server(const GameServerRow& server) {
  postgres::Params p;
  p.text(server.server_id).text(server.host).integer(server.control_port);
  p.integer(server.game_port).text(server.certificate_sha256).text(server.version);
  p.integer(server.capacity).integer(server.players).integer(server.heartbeat_ms);
  p.integer(server.started_ms).integer(server.counted_ms).integer(server.admin_port);
  return execute(Sql::UpsertGameServer, p, "writing a game server's directory row");
}

DbStatus PostgresStore::replace_game_server_matches(std::string_view server_id,
                                                    const std::vector<HostedMatch>& matches) {
  return transaction([&]() -> DbStatus {
    postgres::Params clear;
    clear.text(server_id);
    if (DbStatus s = execute(Sql::DeleteServerMatches, clear, "clearing a game server's matches");
        !s)
      return s;
    for (const HostedMatch& m : matches) {
      postgres::Params p;
      p.text(server_id).integer(m.match_id).text(m.mode).text(m.map);
      p.integer(m.players).integer(m.capacity).integer(m.open ? 1 : 0);
      if (DbStatus s = execute(Sql::InsertServerMatch, p, "writing a game server's match"); !s)
        return s;
    }
    return {};
  });
}

DbResult<std::vector<GameServerRow>> PostgresStore::game_servers(UnixMillis heartbeat_after_ms) {
  postgres::Params p;
  p.integer(heartbeat_after_ms);
  auto r = run(Sql::GameServers, p, "reading the game servers");
  if (!r.ok()) return r.error();
  postgres::Result& q = r.value();
  std::vector<GameServerRow> rows;
  for (int i = 0; i < q.rows(); ++i) {
    GameServerRow row;
    row.server_id = q.text(i, 0);
    row.host = q.text(i, 1);
    row.control_port = static_cast<std::int32_t>(q.integer(i, 2));
    row.game_port = static_cast<std::int32_t>(q.integer(i, 3));
    row.certificate_sha256 = q.text(i, 4);
    row.version = q.text(i, 5);
    row.capacity = static_cast<std::int32_t>(q.integer(i, 6));
    row.players = static_cast<std::int32_t>(q.integer(i, 7));
    row.heartbeat_ms = q.integer(i, 8);
    row.started_ms = q.integer(i, 9);
    row.counted_ms = q.integer(i, 10);
    row.admin_port = static_cast<std::int32_t>(q.integer(i, 11));
    rows.push_back(std::move(row));
  }
  if (!q.column_error().empty()) return bad_row(q, "reading the game servers");
  return rows;
}

DbResult<std::vector<DirectoryMatch>> PostgresStore::directory_matches(
    UnixMillis heartbeat_after_ms) {
  postgres::Params p;
  p.integer(heartbeat_after_ms);
  auto r = run(Sql::DirectoryMatches, p, "reading the game servers' matches");
  if (!r.ok()) return r.error();
  postgres::Result& q = r.value();
  std::vector<DirectoryMatch> rows;
  for (int i = 0; i < q.rows(); ++i) {
    DirectoryMatch row;
    row.server_id = q.text(i, 0);
    row.match.match_id = q.integer(i, 1);
    row.match.mode = q.text(i, 2);
    row.match.map = q.text(i, 3);
    row.match.players = static_cast<std::int32_t>(q.integer(i, 4));
    row.match.capacity = static_cast<std::int32_t>(q.integer(i, 5));
    row.match.open = q.integer(i, 6) != 0;
    rows.push_back(std::move(row));
  }
  if (!q.column_error().empty()) return bad_row(q, "reading the game servers' matches");
  return rows;
}

DbResult<bool> PostgresStore::delete_game_server(std::string_view server_id) {
  return atomically(*this, [&]() -> DbResult<bool> {
    postgres::Params p;
    p.text(server_id);
    if (DbStatus s = execute(Sql::DeleteServerTickets, p, "deleting a game server's tickets"); !s)
      return s.error();
    auto r = run(Sql::DeleteGameServer, p, "deleting a game server");  // matches: ON DELETE CASCADE
    if (!r.ok()) return r.error();
    return r.value().changed() > 0;
  });
}

DbResult<std::int64_t> PostgresStore::delete_game_servers_until(UnixMillis heartbeat_until_ms) {
  return atomically(*this, [&]() -> DbResult<std::int64_t> {
    postgres::Params p;
    p.integer(heartbeat_until_ms);
    if (DbStatus s = execute(Sql::DeleteStaleTickets, p, "deleting stale game servers' tickets");
        !s)
      return s.error();
    auto r = run(Sql::DeleteStaleServers, p, "deleting stale game servers");
    if (!r.ok()) return r.error();
    return r.value().changed();
  });
}

DbStatus PostgresStore::insert_ticket(const TicketRow& ticket) {
  if (ticket.token_hash.size() != kTokenHashBytes)
    return DbError{DbErrorCode::UnknownTicket,
                   "a ticket token hash is " + std::to_string(kTokenHashBytes) + " bytes, got " +
                       std::to_string(ticket.token_hash.size())};
  postgres::Params p;
  p.bytes(ticket.token_hash).integer(ticket.account).text(ticket.server_id);
  p.integer(ticket.match_id).text(ticket.mode).text(ticket.map);
  p.integer(ticket.created_ms).integer(ticket.expires_ms);
  auto r = run(Sql::InsertTicket, p, "inserting a ticket");
  if (!r.ok() && r.error().message.find("tickets_account_id_fkey") != std::string::npos)
    return unknown_account(ticket.account);
  if (!r.ok()) return r.error();
  return {};
}

DbResult<std::optional<TicketRow>> PostgresStore::find_ticket(std::string_view token_hash) {
  if (token_hash.size() != kTokenHashBytes) return std::optional<TicketRow>();
  postgres::Params p;
  p.bytes(token_hash);
  auto r = run(Sql::FindTicket, p, "finding a ticket");
  if (!r.ok()) return r.error();
  postgres::Result& q = r.value();
  if (q.rows() == 0) return std::optional<TicketRow>();
  TicketRow row;
  row.token_hash = std::string(token_hash);
  row.account = q.integer(0, 0);
  row.server_id = q.text(0, 1);
  row.match_id = q.integer(0, 2);
  row.mode = q.text(0, 3);
  row.map = q.text(0, 4);
  row.created_ms = q.integer(0, 5);
  row.expires_ms = q.integer(0, 6);
  row.claimed_ms = q.optional_integer(0, 7);
  if (!q.column_error().empty()) return bad_row(q, "reading a ticket");
  return std::optional<TicketRow>(std::move(row));
}

DbResult<std::vector<HeldSeats>> PostgresStore::held_seats(UnixMillis now) {
  postgres::Params p;
  p.integer(now);
  auto r = run(Sql::HeldSeats, p, "counting held seats");
  if (!r.ok()) return r.error();
  postgres::Result& q = r.value();
  std::vector<HeldSeats> rows;
  for (int i = 0; i < q.rows(); ++i)
    rows.push_back({q.text(i, 0), q.integer(i, 1), q.integer(i, 2), q.integer(i, 3)});
  if (!q.column_error().empty()) return bad_row(q, "counting held seats");
  return rows;
}

DbResult<std::int64_t> PostgresStore::delete_unclaimed_tickets_of(AccountId account) {
  postgres::Params p;
  p.integer(account);
  auto r = run(Sql::DeleteUnclaimedTicketsOf, p, "deleting an account's open tickets");
  if (!r.ok()) return r.error();
  return r.value().changed();
}

DbResult<std::optional<ClaimedTicket>> PostgresStore::claim_ticket(std::string_view token_hash,
                                                                   std::string_view server_id,
                                                                   AccountId account,
                                                                   UnixMillis now) {
  if (token_hash.size() != kTokenHashBytes) return std::optional<ClaimedTicket>();
  postgres::Params p;
  p.bytes(token_hash).text(server_id).integer(account).integer(now);
  auto r = run(Sql::ClaimTicket, p, "claiming a ticket");
  if (!r.ok()) return r.error();
  postgres::Result& q = r.value();
  if (q.rows() == 0) return std::optional<ClaimedTicket>();
  ClaimedTicket claimed{q.integer(0, 0), q.text(0, 1), q.text(0, 2)};
  if (!q.column_error().empty()) return bad_row(q, "claiming a ticket");
  return std::optional<ClaimedTicket>(std::move(claimed));
}

DbResult<std::int64_t> PostgresStore::delete_expired_tickets(UnixMillis now) {
  postgres::Params p;
  p.integer(now);
  auto r = run(Sql::DeleteExpiredTickets, p, "deleting expired tickets");
  if (!r.ok()) return r.error();
  return r.value().changed();
}

}  // namespace

DbResult<std::unique_ptr<Store>> open_postgres_store(const PostgresOptions& options) {
  const std::string where = postgres::describe_url(options.url);
  if (options.url.empty())
    return DbError{DbErrorCode::CannotOpen, "no database URL given (PostgresOptions::url)"};
  if (options.busy_timeout_ms < 0)
    return DbError{DbErrorCode::CannotOpen, where + ": busy_timeout_ms must be >= 0, got " +
                                                std::to_string(options.busy_timeout_ms)};
  postgres::Connection conn = postgres::connect(options.url, options.connect_timeout_s);
  if (!conn) return DbError{DbErrorCode::OutOfMemory, where + ": libpq could not allocate"};
  if (PQstatus(conn.get()) != CONNECTION_OK) {
    std::string message = PQerrorMessage(conn.get());
    while (!message.empty() && (message.back() == '\n' || message.back() == ' '))
      message.pop_back();
    // Refused logins and missing databases are the operator's to fix; anything else (nothing
    // listening, a timeout, the server starting or stopping) may pass.
    const bool refused = message.find("authentication failed") != std::string::npos ||
                         message.find("does not exist") != std::string::npos ||
                         message.find("no pg_hba.conf entry") != std::string::npos ||
                         message.find("password") != std::string::npos;
    if (refused)
      return DbError{DbErrorCode::CannotOpen,
                     where + ": connecting failed: " + message +
                         "; check the user, password and database name in the URL"};
    return DbError{DbErrorCode::Unavailable, where + ": connecting failed: " + message +
                                                 "; the database server is unreachable, retry "
                                                 "later"};
  }
  if (DbStatus s = set_lock_timeout(conn.get(), options.busy_timeout_ms, where); !s)
    return s.error();
  if (auto version = read_postgres_schema_version(conn.get(), where); !version)
    return version.error();
  if (DbStatus s = apply_postgres_migrations(conn.get(), where); !s) return s.error();
  auto store = std::make_unique<PostgresStore>(options, where, std::move(conn));
  if (DbStatus s = store->set_up_connection(); !s) return s.error();
  return std::unique_ptr<Store>(std::move(store));
}

}  // namespace ricochet::db
