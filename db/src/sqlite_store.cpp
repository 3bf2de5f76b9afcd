/// The SQLite Store (store.h): one connection, WAL journal, every statement prepared once at open
/// and bound per call (no SQL is ever built from values).
///
/// Opening, in order: open the file and make it mode 0600 (CannotOpen) → read user_version, the
/// first read, where a file that is not a database fails (CorruptDatabase) and a newer schema is
/// refused (SchemaTooNew) before anything is written → PRAGMA quick_check (CorruptDatabase) →
/// journal_mode=WAL, synchronous, foreign_keys → migrations → prepare the statements.

#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <thread>

#include "leaderboard_sql.h"
#include "migrations.h"
#include "ricochet/db/store.h"
#include "sqlite_handle.h"

namespace ricochet::db {

namespace {

constexpr std::size_t kTokenHashBytes = 32;  ///< SHA-256

constexpr std::array kBoards = {LeaderboardKind::Rating, LeaderboardKind::Kills,
                                LeaderboardKind::WinRate};

std::size_t board_index(LeaderboardKind kind) {
  return static_cast<std::size_t>(kind);
}

class SqliteStore final : public Store {
 public:
  SqliteStore(std::string path, sqlite::Connection db)
      : path_(std::move(path)), db_(std::move(db)) {}

  DbStatus prepare_statements();

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
  DbError failure(int rc, std::string_view what) const {
    return sqlite::error_from(db_.get(), rc, path_, what);
  }
  /// A row that holds a value of the wrong type: the file was edited or damaged.
  DbError bad_row(const sqlite::Query& query, std::string_view what) const {
    return DbError{DbErrorCode::CorruptDatabase,
                   path_ + ": " + std::string(what) + ": " + query.column_error()};
  }
  DbError unknown_account(AccountId id) const {
    return DbError{DbErrorCode::UnknownAccount, "no account with id " + std::to_string(id)};
  }
  /// Runs a statement that returns no rows.
  DbStatus run(sqlite::Query& query, std::string_view what) {
    if (const int rc = query.step(); rc != SQLITE_DONE) return failure(rc, what);
    return {};
  }
  /// Runs an UPDATE of one account by id; UnknownAccount when no row changed.
  DbStatus update_account(sqlite::Query& query, AccountId id, std::string_view what);
  DbResult<MatchId> write_match(const MatchRecord& match,
                                const std::vector<PlayerOutcome>& outcomes);

  std::string path_;
  bool in_transaction_ = false;  ///< inside transaction(): a nested one joins it
  sqlite::Connection db_;        // declared before the statements: closed after they are finalized

  sqlite::Statement insert_account_, find_account_by_key_, account_, set_password_hash_,
      set_banned_, set_last_login_;
  sqlite::Statement insert_session_, find_session_, delete_session_, delete_sessions_of_,
      delete_expired_sessions_;
  sqlite::Statement insert_login_failure_, count_login_failures_, delete_login_failure_,
      delete_login_failures_of_, delete_login_failures_until_;
  sqlite::Statement rating_of_, insert_match_, insert_match_player_, upsert_stats_, match_count_,
      player_stats_, find_match_;
  std::array<sqlite::Statement, kBoards.size()> top_, entry_of_, count_better_;
  sqlite::Statement upsert_game_server_, delete_server_matches_, insert_server_match_,
      game_servers_, directory_matches_, delete_server_tickets_, delete_game_server_,
      delete_stale_tickets_, delete_stale_servers_, insert_ticket_, find_ticket_, held_seats_,
      delete_unclaimed_tickets_of_, claim_ticket_, delete_expired_tickets_;
};

DbStatus SqliteStore::prepare_statements() {
  const std::pair<sqlite::Statement*, const char*> statements[] = {
      {&insert_account_,
       "INSERT INTO accounts (username, username_key, password_hash, created_ms)"
       " VALUES (?1, ?2, ?3, ?4)"},
      {&find_account_by_key_,
       "SELECT id, username, created_ms, last_login_ms, banned, password_hash"
       " FROM accounts WHERE username_key = ?1"},
      {&account_,
       "SELECT id, username, created_ms, last_login_ms, banned FROM accounts WHERE id = ?1"},
      {&set_password_hash_, "UPDATE accounts SET password_hash = ?1 WHERE id = ?2"},
      {&set_banned_, "UPDATE accounts SET banned = ?1 WHERE id = ?2"},
      {&set_last_login_, "UPDATE accounts SET last_login_ms = ?1 WHERE id = ?2"},
      {&insert_session_,
       "INSERT INTO sessions (token_hash, account_id, created_ms, expires_ms)"
       " VALUES (?1, ?2, ?3, ?4)"},
      {&find_session_,
       "SELECT account_id, created_ms, expires_ms FROM sessions WHERE token_hash = ?1"},
      {&delete_session_, "DELETE FROM sessions WHERE token_hash = ?1"},
      {&delete_sessions_of_, "DELETE FROM sessions WHERE account_id = ?1"},
      {&delete_expired_sessions_, "DELETE FROM sessions WHERE expires_ms < ?1"},
      {&insert_login_failure_, "INSERT INTO login_failures (key, at_ms) VALUES (?1, ?2)"},
      {&count_login_failures_, "SELECT COUNT(*) FROM login_failures WHERE key = ?1 AND at_ms > ?2"},
      {&delete_login_failure_, "DELETE FROM login_failures WHERE id = ?1"},
      {&delete_login_failures_of_, "DELETE FROM login_failures WHERE key = ?1"},
      {&delete_login_failures_until_, "DELETE FROM login_failures WHERE at_ms <= ?1"},
      {&rating_of_,
       "SELECT s.rating FROM accounts AS a LEFT JOIN player_stats AS s ON s.account_id = a.id"
       " WHERE a.id = ?1"},
      {&insert_match_,
       "INSERT INTO matches (map, mode, started_ms, ended_ms, tick_rate, aborted, red_score,"
       " blue_score, uuid) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, NULLIF(?9, ''))"},
      {&find_match_,
       "SELECT m.id, p.account_id, p.rating_before, p.rating_after FROM matches AS m"
       " JOIN match_players AS p ON p.match_id = m.id WHERE m.uuid = ?1"},
      {&insert_match_player_,
       "INSERT INTO match_players (match_id, account_id, kills, deaths, score, shots, hits,"
       " damage_dealt, damage_taken, seconds_played, rating_before, rating_after, team)"
       " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13)"},
      {&upsert_stats_,
       "INSERT INTO player_stats (account_id, matches, wins, kills, deaths, score, shots, hits,"
       " damage_dealt, damage_taken, seconds_played, rating)"
       " VALUES (?1, 1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11)"
       " ON CONFLICT (account_id) DO UPDATE SET matches = matches + 1,"
       " wins = wins + excluded.wins, kills = kills + excluded.kills,"
       " deaths = deaths + excluded.deaths, score = score + excluded.score,"
       " shots = shots + excluded.shots, hits = hits + excluded.hits,"
       " damage_dealt = damage_dealt + excluded.damage_dealt,"
       " damage_taken = damage_taken + excluded.damage_taken,"
       " seconds_played = seconds_played + excluded.seconds_played,"
       " rating = excluded.rating"},
      {&match_count_, "SELECT COUNT(*) FROM matches"},
      {&player_stats_,
       "SELECT a.username, s.account_id IS NOT NULL, s.matches, s.wins, s.kills, s.deaths,"
       " s.score, s.shots, s.hits, s.damage_dealt, s.damage_taken, s.seconds_played, s.rating"
       " FROM accounts AS a LEFT JOIN player_stats AS s ON s.account_id = a.id"
       " WHERE a.id = ?1"},
  };
  for (const auto& [statement, sql] : statements)
    if (const int rc = statement->prepare(db_.get(), sql); rc != SQLITE_OK)
      return failure(rc, std::string("preparing \"") + sql + "\"");
  for (LeaderboardKind kind : kBoards) {
    const std::size_t i = board_index(kind);
    for (const auto& [statement, sql] :
         {std::pair{&top_[i], leaderboard_sql::top(kind)},
          std::pair{&entry_of_[i], leaderboard_sql::entry_of(kind)},
          std::pair{&count_better_[i], leaderboard_sql::count_better(kind)}})
      if (const int rc = statement->prepare(db_.get(), sql); rc != SQLITE_OK)
        return failure(rc, std::string("preparing \"") + sql + "\"");
  }
  const std::pair<sqlite::Statement*, const char*> fleet_statements[] = {
      {&upsert_game_server_,
       "INSERT INTO game_servers (server_id, host, control_port, game_port, certificate_sha256,"
       " version, capacity, players, heartbeat_ms, started_ms, counted_ms, admin_port)"
       " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12)"
       " ON CONFLICT (server_id) DO UPDATE SET host = excluded.host,"
       " control_port = excluded.control_port, game_port = excluded.game_port,"
       " certificate_sha256 = excluded.certificate_sha256, version = excluded.version,"
       " capacity = excluded.capacity, players = excluded.players,"
       " heartbeat_ms = excluded.heartbeat_ms, started_ms = excluded.started_ms,"
       " counted_ms = excluded.counted_ms, admin_port = excluded.admin_port"},
      {&delete_server_matches_, "DELETE FROM game_server_matches WHERE server_id = ?1"},
      {&insert_server_match_,
       "INSERT INTO game_server_matches (server_id, match_id, mode, map, players, capacity, open)"
       " VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7)"},
      {&game_servers_,
       "SELECT server_id, host, control_port, game_port, certificate_sha256, version, capacity,"
       " players, heartbeat_ms, started_ms, counted_ms, admin_port FROM game_servers WHERE "
       "heartbeat_ms > ?1"
       " ORDER BY server_id"},
      {&directory_matches_,
       "SELECT m.server_id, m.match_id, m.mode, m.map, m.players, m.capacity, m.open"
       " FROM game_server_matches AS m JOIN game_servers AS s ON s.server_id = m.server_id"
       " WHERE s.heartbeat_ms > ?1 ORDER BY m.server_id, m.match_id"},
      {&delete_server_tickets_, "DELETE FROM tickets WHERE server_id = ?1 AND claimed_ms IS NULL"},
      {&delete_game_server_, "DELETE FROM game_servers WHERE server_id = ?1"},
      {&delete_stale_tickets_,
       "DELETE FROM tickets WHERE server_id IN"
       " (SELECT server_id FROM game_servers WHERE heartbeat_ms <= ?1)"},
      {&delete_stale_servers_, "DELETE FROM game_servers WHERE heartbeat_ms <= ?1"},
      {&insert_ticket_,
       "INSERT INTO tickets (token_hash, account_id, server_id, match_id, mode, map, created_ms,"
       " expires_ms) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8)"},
      {&find_ticket_,
       "SELECT account_id, server_id, match_id, mode, map, created_ms, expires_ms, claimed_ms"
       " FROM tickets WHERE token_hash = ?1"},
      {&held_seats_,
       "SELECT t.server_id, t.match_id, COUNT(*), COUNT(t.claimed_ms) FROM tickets AS t"
       " JOIN game_servers AS s ON s.server_id = t.server_id"
       " WHERE (t.claimed_ms IS NULL AND t.expires_ms > ?1) OR t.claimed_ms >= s.counted_ms"
       " GROUP BY t.server_id, t.match_id ORDER BY t.server_id, t.match_id"},
      {&delete_unclaimed_tickets_of_,
       "DELETE FROM tickets WHERE account_id = ?1 AND claimed_ms IS NULL"},
      {&claim_ticket_,
       "UPDATE tickets SET claimed_ms = ?4 WHERE token_hash = ?1 AND claimed_ms IS NULL"
       " AND server_id = ?2 AND account_id = ?3 AND expires_ms > ?4"
       " RETURNING match_id, mode, map"},
      {&delete_expired_tickets_, "DELETE FROM tickets WHERE expires_ms <= ?1"},
  };
  for (const auto& [statement, sql] : fleet_statements)
    if (const int rc = statement->prepare(db_.get(), sql); rc != SQLITE_OK)
      return failure(rc, std::string("preparing \"") + sql + "\"");
  return {};
}

DbStatus SqliteStore::transaction(const std::function<DbStatus()>& work) {
  if (in_transaction_) return work();
  sqlite::Transaction transaction(db_.get());
  if (const int rc = transaction.begin(); rc != SQLITE_OK)
    return failure(rc, "starting a transaction");
  struct Inside {
    bool& flag;
    ~Inside() { flag = false; }
  };
  in_transaction_ = true;
  const Inside inside{in_transaction_};
  const DbStatus status = work();
  if (!status.ok()) return status;  // rolled back by ~Transaction
  if (const int rc = transaction.commit(); rc != SQLITE_OK)
    return failure(rc, "committing a transaction");
  return {};
}

// --- accounts ---

DbResult<AccountId> SqliteStore::insert_account(std::string_view username,
                                                std::string_view username_key,
                                                std::string_view password_hash, UnixMillis now) {
  sqlite::Query q(insert_account_);
  q.bind_text(username).bind_text(username_key).bind_text(password_hash).bind_int(now);
  const int rc = q.step();
  if (rc == SQLITE_CONSTRAINT_UNIQUE)
    return DbError{DbErrorCode::DuplicateUsername,
                   "username '" + std::string(username) + "' is taken (ignoring case)"};
  if (rc != SQLITE_DONE) return failure(rc, "inserting an account");
  return sqlite3_last_insert_rowid(db_.get());
}

DbResult<std::optional<AccountCredentials>> SqliteStore::find_account_by_key(
    std::string_view username_key) {
  sqlite::Query q(find_account_by_key_);
  q.bind_text(username_key);
  const int rc = q.step();
  if (rc == SQLITE_DONE) return std::optional<AccountCredentials>();
  if (rc != SQLITE_ROW) return failure(rc, "finding an account by name");
  AccountCredentials found;
  found.account.id = q.integer(0);
  found.account.username = q.text(1);
  found.account.created_ms = q.integer(2);
  found.account.last_login_ms = q.optional_integer(3);
  found.account.banned = q.integer(4) != 0;
  found.password_hash = q.text(5);
  if (!q.column_error().empty()) return bad_row(q, "reading an account");
  return std::optional<AccountCredentials>(std::move(found));
}

DbResult<Account> SqliteStore::account(AccountId id) {
  sqlite::Query q(account_);
  q.bind_int(id);
  const int rc = q.step();
  if (rc == SQLITE_DONE) return unknown_account(id);
  if (rc != SQLITE_ROW) return failure(rc, "reading an account");
  Account found;
  found.id = q.integer(0);
  found.username = q.text(1);
  found.created_ms = q.integer(2);
  found.last_login_ms = q.optional_integer(3);
  found.banned = q.integer(4) != 0;
  if (!q.column_error().empty()) return bad_row(q, "reading an account");
  return found;
}

DbStatus SqliteStore::update_account(sqlite::Query& query, AccountId id, std::string_view what) {
  query.bind_int(id);
  if (const int rc = query.step(); rc != SQLITE_DONE) return failure(rc, what);
  if (sqlite3_changes64(db_.get()) == 0) return unknown_account(id);
  return {};
}

DbStatus SqliteStore::set_password_hash(AccountId id, std::string_view password_hash) {
  sqlite::Query q(set_password_hash_);
  q.bind_text(password_hash);
  return update_account(q, id, "setting a password hash");
}

DbStatus SqliteStore::set_banned(AccountId id, bool banned) {
  sqlite::Query q(set_banned_);
  q.bind_int(banned ? 1 : 0);
  return update_account(q, id, "setting the banned flag");
}

DbStatus SqliteStore::set_last_login(AccountId id, UnixMillis now) {
  sqlite::Query q(set_last_login_);
  q.bind_int(now);
  return update_account(q, id, "setting the last login time");
}

// --- sessions ---

/// UnknownSession for a hash of the wrong size: the caller passes SHA-256 digests only.
DbStatus check_token_hash(std::string_view token_hash) {
  if (token_hash.size() == kTokenHashBytes) return {};
  return DbError{DbErrorCode::UnknownSession, "a session token hash is " +
                                                  std::to_string(kTokenHashBytes) + " bytes, got " +
                                                  std::to_string(token_hash.size())};
}

DbStatus SqliteStore::insert_session(std::string_view token_hash, AccountId account,
                                     UnixMillis created_ms, UnixMillis expires_ms) {
  if (DbStatus s = check_token_hash(token_hash); !s) return s;
  sqlite::Query q(insert_session_);
  q.bind_blob(token_hash).bind_int(account).bind_int(created_ms).bind_int(expires_ms);
  const int rc = q.step();
  if (rc == SQLITE_CONSTRAINT_FOREIGNKEY) return unknown_account(account);
  if (rc != SQLITE_DONE) return failure(rc, "inserting a session");
  return {};
}

DbResult<std::optional<SessionRow>> SqliteStore::find_session(std::string_view token_hash) {
  if (token_hash.size() != kTokenHashBytes) return std::optional<SessionRow>();
  sqlite::Query q(find_session_);
  q.bind_blob(token_hash);
  const int rc = q.step();
  if (rc == SQLITE_DONE) return std::optional<SessionRow>();
  if (rc != SQLITE_ROW) return failure(rc, "finding a session");
  SessionRow row;
  row.account = q.integer(0);
  row.created_ms = q.integer(1);
  row.expires_ms = q.integer(2);
  if (!q.column_error().empty()) return bad_row(q, "reading a session");
  return std::optional<SessionRow>(row);
}

DbStatus SqliteStore::delete_session(std::string_view token_hash) {
  if (token_hash.size() != kTokenHashBytes) return {};  // no such session can exist
  sqlite::Query q(delete_session_);
  q.bind_blob(token_hash);
  return run(q, "deleting a session");
}

DbStatus SqliteStore::delete_sessions_of(AccountId account) {
  sqlite::Query q(delete_sessions_of_);
  q.bind_int(account);
  return run(q, "deleting the sessions of an account");
}

DbResult<std::int64_t> SqliteStore::delete_expired_sessions(UnixMillis now) {
  sqlite::Query q(delete_expired_sessions_);
  q.bind_int(now);
  if (const int rc = q.step(); rc != SQLITE_DONE) return failure(rc, "deleting expired sessions");
  return static_cast<std::int64_t>(sqlite3_changes64(db_.get()));
}

// --- failed logins ---

DbResult<std::int64_t> SqliteStore::insert_login_failure(std::string_view key, UnixMillis at_ms) {
  sqlite::Query q(insert_login_failure_);
  q.bind_text(key).bind_int(at_ms);
  if (DbStatus s = run(q, "noting a failed login"); !s.ok()) return s.error();
  return sqlite3_last_insert_rowid(db_.get());
}

DbResult<std::int64_t> SqliteStore::count_login_failures(std::string_view key,
                                                         UnixMillis after_ms) {
  sqlite::Query q(count_login_failures_);
  q.bind_text(key).bind_int(after_ms);
  if (const int rc = q.step(); rc != SQLITE_ROW) return failure(rc, "counting failed logins");
  const std::int64_t count = q.integer(0);
  if (!q.column_error().empty()) return bad_row(q, "counting failed logins");
  return count;
}

DbStatus SqliteStore::delete_login_failure(std::int64_t id) {
  sqlite::Query q(delete_login_failure_);
  q.bind_int(id);
  return run(q, "forgetting a failed login");
}

DbStatus SqliteStore::delete_login_failures_of(std::string_view key) {
  sqlite::Query q(delete_login_failures_of_);
  q.bind_text(key);
  return run(q, "forgetting the failed logins of a key");
}

DbStatus SqliteStore::delete_login_failures_until(UnixMillis at_ms) {
  sqlite::Query q(delete_login_failures_until_);
  q.bind_int(at_ms);
  return run(q, "dropping old failed logins");
}

// --- matches and stats ---

DbResult<std::optional<double>> SqliteStore::rating_of(AccountId id) {
  sqlite::Query q(rating_of_);
  q.bind_int(id);
  const int rc = q.step();
  if (rc == SQLITE_DONE) return unknown_account(id);
  if (rc != SQLITE_ROW) return failure(rc, "reading a player's rating");
  std::optional<double> rating;
  if (!q.is_null(0)) rating = q.real(0);
  if (!q.column_error().empty()) return bad_row(q, "reading a player's rating");
  return rating;
}

DbResult<MatchId> SqliteStore::write_match(const MatchRecord& match,
                                           const std::vector<PlayerOutcome>& outcomes) {
  MatchId id = 0;
  {
    sqlite::Query q(insert_match_);
    q.bind_text(match.map).bind_text(match.mode).bind_int(match.started_ms);
    q.bind_int(match.ended_ms).bind_int(match.tick_rate).bind_int(match.aborted ? 1 : 0);
    q.bind_int(match.team_scores.red).bind_int(match.team_scores.blue);
    q.bind_text(match.uuid);
    if (const int rc = q.step(); rc != SQLITE_DONE) return failure(rc, "inserting a match");
    id = sqlite3_last_insert_rowid(db_.get());
  }
  for (std::size_t i = 0; i < match.players.size(); ++i) {
    const PlayerResult& p = match.players[i];
    sqlite::Query q(insert_match_player_);
    q.bind_int(id).bind_int(p.account).bind_int(p.kills).bind_int(p.deaths).bind_int(p.score);
    q.bind_int(p.shots).bind_int(p.hits).bind_real(p.damage_dealt).bind_real(p.damage_taken);
    q.bind_real(p.seconds_played).bind_real(outcomes[i].rating_before);
    q.bind_real(outcomes[i].rating_after).bind_int(p.team);
    if (const int rc = q.step(); rc != SQLITE_DONE) return failure(rc, "inserting a match player");
  }
  for (std::size_t i = 0; i < match.players.size(); ++i) {
    const PlayerResult& p = match.players[i];
    sqlite::Query q(upsert_stats_);
    q.bind_int(p.account).bind_int(outcomes[i].won ? 1 : 0).bind_int(p.kills);
    q.bind_int(p.deaths).bind_int(p.score).bind_int(p.shots).bind_int(p.hits);
    q.bind_real(p.damage_dealt).bind_real(p.damage_taken).bind_real(p.seconds_played);
    q.bind_real(outcomes[i].rating_after);
    if (const int rc = q.step(); rc != SQLITE_DONE) return failure(rc, "updating a player's stats");
  }
  return id;
}

DbResult<MatchId> SqliteStore::insert_match(const MatchRecord& match,
                                            const std::vector<PlayerOutcome>& outcomes) {
  if (outcomes.size() != match.players.size()) {
    return DbError{DbErrorCode::InvalidMatch, "a match of " + std::to_string(match.players.size()) +
                                                  " players needs as many outcomes, got " +
                                                  std::to_string(outcomes.size())};
  }
  return atomically(*this, [&] { return write_match(match, outcomes); });
}

DbResult<std::optional<StoredMatch>> SqliteStore::find_match(std::string_view uuid) {
  sqlite::Query q(find_match_);
  q.bind_text(uuid);
  std::optional<StoredMatch> found;
  int rc = SQLITE_ROW;
  while ((rc = q.step()) == SQLITE_ROW) {
    if (!found) found.emplace().id = q.integer(0);
    found->accounts.push_back(q.integer(1));
    found->outcomes.push_back({q.real(2), q.real(3), false});
  }
  if (rc != SQLITE_DONE) return failure(rc, "finding a match by its uuid");
  if (!q.column_error().empty()) return bad_row(q, "finding a match by its uuid");
  return found;
}

DbResult<std::int64_t> SqliteStore::match_count() {
  sqlite::Query q(match_count_);
  if (const int rc = q.step(); rc != SQLITE_ROW) return failure(rc, "counting matches");
  const std::int64_t count = q.integer(0);
  if (!q.column_error().empty()) return bad_row(q, "counting matches");
  return count;
}

DbResult<PlayerStats> SqliteStore::player_stats(AccountId id) {
  sqlite::Query q(player_stats_);
  q.bind_int(id);
  const int rc = q.step();
  if (rc == SQLITE_DONE) return unknown_account(id);
  if (rc != SQLITE_ROW) return failure(rc, "reading player stats");
  PlayerStats stats;
  stats.account = id;
  stats.username = q.text(0);
  if (q.integer(1) != 0) {  // has a stats row
    stats.matches = q.integer(2);
    stats.wins = q.integer(3);
    stats.kills = q.integer(4);
    stats.deaths = q.integer(5);
    stats.score = q.integer(6);
    stats.shots = q.integer(7);
    stats.hits = q.integer(8);
    stats.damage_dealt = q.real(9);
    stats.damage_taken = q.real(10);
    stats.seconds_played = q.real(11);
    stats.rating = q.real(12);
  }
  if (!q.column_error().empty()) return bad_row(q, "reading player stats");
  return stats;
}

// --- leaderboards ---

/// Reads a board value: kills are integers, rating and win rate reals.
double board_value(sqlite::Query& q, int column, LeaderboardKind kind) {
  return kind == LeaderboardKind::Kills ? static_cast<double>(q.integer(column)) : q.real(column);
}

DbResult<std::vector<LeaderboardEntry>> SqliteStore::leaderboard(LeaderboardKind kind, int limit,
                                                                 std::int64_t min_matches) {
  std::vector<LeaderboardEntry> entries;
  if (limit <= 0) return entries;  // SQLite reads a negative LIMIT as "no limit"
  sqlite::Query q(top_[board_index(kind)]);
  q.bind_int(limit);
  if (kind == LeaderboardKind::WinRate) q.bind_int(min_matches);
  int rc;
  while ((rc = q.step()) == SQLITE_ROW) {
    LeaderboardEntry e;
    e.account = q.integer(0);
    e.username = q.text(1);
    e.value = board_value(q, 2, kind);
    e.matches = q.integer(3);
    if (!q.column_error().empty()) return bad_row(q, "reading a leaderboard");
    entries.push_back(std::move(e));
  }
  if (rc != SQLITE_DONE) return failure(rc, "reading a leaderboard");
  return entries;
}

DbResult<std::optional<LeaderboardEntry>> SqliteStore::board_entry(AccountId id,
                                                                   LeaderboardKind kind) {
  sqlite::Query q(entry_of_[board_index(kind)]);
  q.bind_int(id);
  const int rc = q.step();
  if (rc == SQLITE_DONE) return unknown_account(id);
  if (rc != SQLITE_ROW) return failure(rc, "reading a leaderboard entry");
  if (q.is_null(1)) return std::optional<LeaderboardEntry>();  // never played
  LeaderboardEntry e;
  e.account = id;
  e.username = q.text(0);
  e.matches = q.integer(1);
  e.value = board_value(q, 2, kind);
  if (!q.column_error().empty()) return bad_row(q, "reading a leaderboard entry");
  return std::optional<LeaderboardEntry>(std::move(e));
}

DbResult<std::int64_t> SqliteStore::count_better(LeaderboardKind kind, double value,
                                                 std::int64_t min_matches) {
  sqlite::Query q(count_better_[board_index(kind)]);
  if (kind == LeaderboardKind::Kills)
    q.bind_int(static_cast<std::int64_t>(value));
  else
    q.bind_real(value);
  if (kind == LeaderboardKind::WinRate) q.bind_int(min_matches);
  if (const int rc = q.step(); rc != SQLITE_ROW) return failure(rc, "ranking an account");
  const std::int64_t better = q.integer(0);
  if (!q.column_error().empty()) return bad_row(q, "ranking an account");
  return better;
}

// --- fleet directory and tickets ---

DbStatus SqliteStore::upsert_game_server(const GameServerRow& server) {
  sqlite::Query q(upsert_game_server_);
  q.bind_text(server.server_id).bind_text(server.host).bind_int(server.control_port);
  q.bind_int(server.game_port).bind_text(server.certificate_sha256).bind_text(server.version);
  q.bind_int(server.capacity).bind_int(server.players).bind_int(server.heartbeat_ms);
  q.bind_int(server.started_ms).bind_int(server.counted_ms).bind_int(server.admin_port);
  return run(q, "writing a game server's directory row");
}

DbStatus SqliteStore::replace_game_server_matches(std::string_view server_id,
                                                  const std::vector<HostedMatch>& matches) {
  return transaction([&]() -> DbStatus {
    sqlite::Query clear(delete_server_matches_);
    clear.bind_text(server_id);
    if (DbStatus s = run(clear, "clearing a game server's matches"); !s) return s;
    for (const HostedMatch& m : matches) {
      sqlite::Query q(insert_server_match_);
      q.bind_text(server_id).bind_int(m.match_id).bind_text(m.mode).bind_text(m.map);
      q.bind_int(m.players).bind_int(m.capacity).bind_int(m.open ? 1 : 0);
      if (DbStatus s = run(q, "writing a game server's match"); !s) return s;
    }
    return {};
  });
}

DbResult<std::vector<GameServerRow>> SqliteStore::game_servers(UnixMillis heartbeat_after_ms) {
  sqlite::Query q(game_servers_);
  q.bind_int(heartbeat_after_ms);
  std::vector<GameServerRow> rows;
  int rc;
  while ((rc = q.step()) == SQLITE_ROW) {
    GameServerRow row;
    row.server_id = q.text(0);
    row.host = q.text(1);
    row.control_port = static_cast<std::int32_t>(q.integer(2));
    row.game_port = static_cast<std::int32_t>(q.integer(3));
    row.certificate_sha256 = q.text(4);
    row.version = q.text(5);
    row.capacity = static_cast<std::int32_t>(q.integer(6));
    row.players = static_cast<std::int32_t>(q.integer(7));
    row.heartbeat_ms = q.integer(8);
    row.started_ms = q.integer(9);
    row.counted_ms = q.integer(10);
    row.admin_port = static_cast<std::int32_t>(q.integer(11));
    if (!q.column_error().empty()) return bad_row(q, "reading the game servers");
    rows.push_back(std::move(row));
  }
  if (rc != SQLITE_DONE) return failure(rc, "reading the game servers");
  return rows;
}

DbResult<std::vector<DirectoryMatch>> SqliteStore::directory_matches(
    UnixMillis heartbeat_after_ms) {
  sqlite::Query q(directory_matches_);
  q.bind_int(heartbeat_after_ms);
  std::vector<DirectoryMatch> rows;
  int rc;
  while ((rc = q.step()) == SQLITE_ROW) {
    DirectoryMatch row;
    row.server_id = q.text(0);
    row.match.match_id = q.integer(1);
    row.match.mode = q.text(2);
    row.match.map = q.text(3);
    row.match.players = static_cast<std::int32_t>(q.integer(4));
    row.match.capacity = static_cast<std::int32_t>(q.integer(5));
    row.match.open = q.integer(6) != 0;
    if (!q.column_error().empty()) return bad_row(q, "reading the game servers' matches");
    rows.push_back(std::move(row));
  }
  if (rc != SQLITE_DONE) return failure(rc, "reading the game servers' matches");
  return rows;
}

DbResult<bool> SqliteStore::delete_game_server(std::string_view server_id) {
  return atomically(*this, [&]() -> DbResult<bool> {
    sqlite::Query tickets(delete_server_tickets_);
    tickets.bind_text(server_id);
    if (DbStatus s = run(tickets, "deleting a game server's tickets"); !s) return s.error();
    sqlite::Query q(delete_game_server_);  // its matches go by ON DELETE CASCADE
    q.bind_text(server_id);
    if (DbStatus s = run(q, "deleting a game server"); !s) return s.error();
    return sqlite3_changes64(db_.get()) > 0;
  });
}

DbResult<std::int64_t> SqliteStore::delete_game_servers_until(UnixMillis heartbeat_until_ms) {
  return atomically(*this, [&]() -> DbResult<std::int64_t> {
    sqlite::Query tickets(delete_stale_tickets_);
    tickets.bind_int(heartbeat_until_ms);
    if (DbStatus s = run(tickets, "deleting stale game servers' tickets"); !s) return s.error();
    sqlite::Query q(delete_stale_servers_);
    q.bind_int(heartbeat_until_ms);
    if (DbStatus s = run(q, "deleting stale game servers"); !s) return s.error();
    return static_cast<std::int64_t>(sqlite3_changes64(db_.get()));
  });
}

/// UnknownTicket for a hash of the wrong size: the caller passes SHA-256 digests only.
DbStatus check_ticket_hash(std::string_view token_hash) {
  if (token_hash.size() == kTokenHashBytes) return {};
  return DbError{DbErrorCode::UnknownTicket, "a ticket token hash is " +
                                                 std::to_string(kTokenHashBytes) + " bytes, got " +
                                                 std::to_string(token_hash.size())};
}

DbStatus SqliteStore::insert_ticket(const TicketRow& ticket) {
  if (DbStatus s = check_ticket_hash(ticket.token_hash); !s) return s;
  sqlite::Query q(insert_ticket_);
  q.bind_blob(ticket.token_hash).bind_int(ticket.account).bind_text(ticket.server_id);
  q.bind_int(ticket.match_id).bind_text(ticket.mode).bind_text(ticket.map);
  q.bind_int(ticket.created_ms).bind_int(ticket.expires_ms);
  const int rc = q.step();
  if (rc == SQLITE_CONSTRAINT_FOREIGNKEY) return unknown_account(ticket.account);
  if (rc != SQLITE_DONE) return failure(rc, "inserting a ticket");
  return {};
}

DbResult<std::optional<TicketRow>> SqliteStore::find_ticket(std::string_view token_hash) {
  if (token_hash.size() != kTokenHashBytes) return std::optional<TicketRow>();
  sqlite::Query q(find_ticket_);
  q.bind_blob(token_hash);
  const int rc = q.step();
  if (rc == SQLITE_DONE) return std::optional<TicketRow>();
  if (rc != SQLITE_ROW) return failure(rc, "finding a ticket");
  TicketRow row;
  row.token_hash = std::string(token_hash);
  row.account = q.integer(0);
  row.server_id = q.text(1);
  row.match_id = q.integer(2);
  row.mode = q.text(3);
  row.map = q.text(4);
  row.created_ms = q.integer(5);
  row.expires_ms = q.integer(6);
  row.claimed_ms = q.optional_integer(7);
  if (!q.column_error().empty()) return bad_row(q, "reading a ticket");
  return std::optional<TicketRow>(std::move(row));
}

DbResult<std::vector<HeldSeats>> SqliteStore::held_seats(UnixMillis now) {
  sqlite::Query q(held_seats_);
  q.bind_int(now);
  std::vector<HeldSeats> rows;
  int rc;
  while ((rc = q.step()) == SQLITE_ROW) {
    HeldSeats row;
    row.server_id = q.text(0);
    row.match_id = q.integer(1);
    row.seats = q.integer(2);
    row.claimed = q.integer(3);
    if (!q.column_error().empty()) return bad_row(q, "counting held seats");
    rows.push_back(std::move(row));
  }
  if (rc != SQLITE_DONE) return failure(rc, "counting held seats");
  return rows;
}

DbResult<std::int64_t> SqliteStore::delete_unclaimed_tickets_of(AccountId account) {
  sqlite::Query q(delete_unclaimed_tickets_of_);
  q.bind_int(account);
  if (DbStatus s = run(q, "deleting an account's open tickets"); !s) return s.error();
  return static_cast<std::int64_t>(sqlite3_changes64(db_.get()));
}

DbResult<std::optional<ClaimedTicket>> SqliteStore::claim_ticket(std::string_view token_hash,
                                                                 std::string_view server_id,
                                                                 AccountId account,
                                                                 UnixMillis now) {
  if (token_hash.size() != kTokenHashBytes) return std::optional<ClaimedTicket>();
  sqlite::Query q(claim_ticket_);
  q.bind_blob(token_hash).bind_text(server_id).bind_int(account).bind_int(now);
  const int rc = q.step();
  if (rc == SQLITE_DONE) return std::optional<ClaimedTicket>();
  if (rc != SQLITE_ROW) return failure(rc, "claiming a ticket");
  ClaimedTicket claimed;
  claimed.match_id = q.integer(0);
  claimed.mode = q.text(1);
  claimed.map = q.text(2);
  if (!q.column_error().empty()) return bad_row(q, "claiming a ticket");
  // The change is made by the first step; the statement ends (and commits) at SQLITE_DONE.
  if (const int done = q.step(); done != SQLITE_DONE) return failure(done, "claiming a ticket");
  return std::optional<ClaimedTicket>(std::move(claimed));
}

DbResult<std::int64_t> SqliteStore::delete_expired_tickets(UnixMillis now) {
  sqlite::Query q(delete_expired_tickets_);
  q.bind_int(now);
  if (DbStatus s = run(q, "deleting expired tickets"); !s) return s.error();
  return static_cast<std::int64_t>(sqlite3_changes64(db_.get()));
}

// --- opening ---

/// Runs a PRAGMA that answers with one text row and checks the answer.
DbStatus set_pragma(sqlite3* db, const std::string& path, const char* sql, const char* expected) {
  std::string answer;
  if (const int rc = sqlite::single_text(db, sql, answer); rc != SQLITE_OK)
    return sqlite::error_from(db, rc, path, sql);
  if (answer != expected)
    return DbError{DbErrorCode::Storage,
                   path + ": " + sql + " answered '" + answer + "', expected '" + expected + "'"};
  return {};
}

DbStatus check_integrity(sqlite3* db, const std::string& path) {
  std::string answer;
  if (const int rc = sqlite::single_text(db, "PRAGMA quick_check", answer); rc != SQLITE_OK)
    return sqlite::error_from(db, rc, path, "PRAGMA quick_check");
  if (answer != "ok")
    return DbError{DbErrorCode::CorruptDatabase, path +
                                                     " is damaged (PRAGMA quick_check: " + answer +
                                                     "); restore it from a backup or move it away"};
  return {};
}

DbStatus configure(sqlite3* db, const SqliteOptions& options) {
  const std::string& path = options.path;
  // WAL: readers never block the writer, and a commit is one append to the log. Switching needs
  // the exclusive lock, and SQLite answers SQLITE_BUSY at once (without the busy handler, to
  // avoid a deadlock) while another connection is migrating the same new file: try again until
  // the busy timeout has passed.
  DbStatus wal = set_pragma(db, path, "PRAGMA journal_mode = WAL", "wal");
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::milliseconds(options.busy_timeout_ms);
  while (!wal && wal.error().code == DbErrorCode::Busy &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    wal = set_pragma(db, path, "PRAGMA journal_mode = WAL", "wal");
  }
  if (DbStatus s = wal; !s) {
    DbError e = s.error();
    if (e.code == DbErrorCode::Storage)
      e.message += "; WAL needs a database file on a local filesystem";
    return e;
  }
  const char* synchronous =
      options.synchronous_full ? "PRAGMA synchronous = FULL" : "PRAGMA synchronous = NORMAL";
  if (const int rc = sqlite::exec(db, synchronous); rc != SQLITE_OK)
    return sqlite::error_from(db, rc, path, synchronous);
  if (const int rc = sqlite::exec(db, "PRAGMA foreign_keys = ON"); rc != SQLITE_OK)
    return sqlite::error_from(db, rc, path, "PRAGMA foreign_keys = ON");
  // Setting the pragma is silently ignored by an SQLite built without foreign keys.
  return set_pragma(db, path, "PRAGMA foreign_keys", "1");
}

}  // namespace

DbResult<std::unique_ptr<Store>> open_sqlite_store(const SqliteOptions& options) {
  const std::string& path = options.path;
  if (path.empty())
    return DbError{DbErrorCode::CannotOpen, "no database file given (SqliteOptions::path)"};
  if (options.busy_timeout_ms < 0)
    return DbError{DbErrorCode::CannotOpen, path + ": busy_timeout_ms must be >= 0, got " +
                                                std::to_string(options.busy_timeout_ms)};
  sqlite::Connection db;  // closed on every return below, even when opening failed
  const int rc = sqlite::open(
      path,
      SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX | SQLITE_OPEN_EXRESCODE, db);
  if (rc != SQLITE_OK) {
    DbError e = sqlite::error_from(db.get(), rc, path, "opening the database");
    e.code = DbErrorCode::CannotOpen;
    return e;
  }
  // SQLite falls back to read-only when the file cannot be written; the store must write.
  if (sqlite3_db_readonly(db.get(), "main") == 1)
    return DbError{DbErrorCode::CannotOpen,
                   path + " can only be opened read-only; check the file's permissions"};
  // It holds password hashes and session tokens: the owner's alone. SQLite gives the -wal and
  // -shm files it makes later the database file's mode.
  if (path != ":memory:" && ::chmod(path.c_str(), 0600) != 0)
    return DbError{DbErrorCode::CannotOpen,
                   path + ": cannot make it private (mode 0600): " + std::strerror(errno)};
  sqlite3_busy_timeout(db.get(), options.busy_timeout_ms);

  if (auto version = read_schema_version(db.get(), path); !version) return version.error();
  if (DbStatus s = check_integrity(db.get(), path); !s) return s.error();
  if (DbStatus s = configure(db.get(), options); !s) return s.error();
  if (DbStatus s = apply_migrations(db.get(), path); !s) return s.error();

  auto store = std::make_unique<SqliteStore>(path, std::move(db));
  if (DbStatus s = store->prepare_statements(); !s) return s.error();
  return std::unique_ptr<Store>(std::move(store));
}

}  // namespace ricochet::db
