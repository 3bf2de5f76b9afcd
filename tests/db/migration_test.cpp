// Opening and migrating SQLite files: a new file ends at the current schema version, reopening
// changes nothing, concurrent first opens migrate once, and files that cannot be used (newer
// schema, not a database, truncated, a directory, a missing directory) are refused with the
// path in the message and without a crash. Also checks that the connection settings (WAL,
// synchronous, foreign keys, busy timeout) are really in effect on the store's connection.

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include "db_test_util.h"
#include "migrations.h"
#include "postgres_migrations.h"
#include "ricochet/db/matches.h"
#include "ricochet/db/store.h"
#include "sqlite_handle.h"
#include "store_fixture.h"

namespace ricochet::db::test::migration_test {
namespace {

namespace fs = std::filesystem;

DbResult<std::unique_ptr<Store>> open_store(const std::string& path) {
  SqliteOptions options;
  options.path = path;
  return open_sqlite_store(options);
}

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

std::int64_t raw_integer(const std::string& path, const std::string& sql) {
  sqlite::Connection raw;
  EXPECT_EQ(sqlite::open(path, SQLITE_OPEN_READONLY, raw), SQLITE_OK);
  std::int64_t value = -1;
  EXPECT_EQ(sqlite::single_integer(raw.get(), sql, value), SQLITE_OK)
      << sql << ": " << sqlite3_errmsg(raw.get());
  return value;
}

/// Files in `dir`, by name.
std::vector<std::string> files_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename());
  std::sort(names.begin(), names.end());
  return names;
}

::testing::AssertionResult mentions(const DbError& error, const std::string& text) {
  if (error.message.find(text) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "'" << error.message << "' does not mention '" << text << "'";
}

TEST(MigrationTest, VersionsAreNumberedFromOne) {
  const auto migrations = sqlite_migrations();
  ASSERT_FALSE(migrations.empty());
  for (std::size_t i = 0; i < migrations.size(); ++i)
    EXPECT_EQ(migrations[i].version, static_cast<int>(i) + 1);
  EXPECT_EQ(migrations.back().version, sqlite_schema_version());
}

TEST(MigrationTest, NewFileEndsAtTheCurrentVersion) {
  TempDir dir;
  const std::string path = dir.file("new.db");
  must(open_store(path), "open");
  EXPECT_EQ(raw_integer(path, "PRAGMA user_version"), sqlite_schema_version());
  EXPECT_EQ(raw_integer(path,
                        "SELECT COUNT(*) FROM sqlite_schema WHERE type = 'table' AND name IN"
                        " ('accounts', 'sessions', 'matches', 'match_players', 'player_stats')"),
            5);
}

TEST(MigrationTest, AVersion1FileGainsTheLoginFailuresAndKeepsItsData) {
  TempDir dir;
  const std::string path = dir.file("v1.db");
  {
    // A file as the version-1 binary left it, with one account.
    sqlite::Connection raw;
    ASSERT_EQ(sqlite::open(path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, raw), SQLITE_OK);
    ASSERT_EQ(sqlite::exec(raw.get(), sqlite_migrations()[0].sql), SQLITE_OK)
        << sqlite3_errmsg(raw.get());
    ASSERT_EQ(sqlite::exec(raw.get(),
                           "INSERT INTO accounts (username, username_key, password_hash,"
                           " created_ms) VALUES ('Old', 'old', 'h', 7); PRAGMA user_version = 1"),
              SQLITE_OK)
        << sqlite3_errmsg(raw.get());
  }
  auto store = must(open_store(path), "open a version-1 file");
  EXPECT_EQ(raw_integer(path, "PRAGMA user_version"), sqlite_schema_version());
  const auto old = must(store->find_account_by_key("old"), "the old account");
  ASSERT_TRUE(old.has_value());
  EXPECT_EQ(old->account.created_ms, 7);
  const std::int64_t id = must(store->insert_login_failure("account:old", 100), "insert");
  EXPECT_EQ(must(store->count_login_failures("account:old", 99), "count"), 1);
  RICOCHET_DB_EXPECT_OK(store->delete_login_failure(id));
  EXPECT_EQ(must(store->count_login_failures("account:old", 0), "count after delete"), 0);
}

TEST(MigrationTest, AVersion2FileGainsTeamsAndAbortedMatchesAndKeepsItsData) {
  TempDir dir;
  const std::string path = dir.file("v2.db");
  {
    // A file as the version-2 binary left it: two accounts and one free-for-all match they
    // played, with their results and lifetime stats, written with that version's statements.
    sqlite::Connection raw;
    ASSERT_EQ(sqlite::open(path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, raw), SQLITE_OK);
    for (const Migration& m : sqlite_migrations().first(2))
      ASSERT_EQ(sqlite::exec(raw.get(), m.sql), SQLITE_OK) << sqlite3_errmsg(raw.get());
    ASSERT_EQ(
        sqlite::exec(
            raw.get(),
            "INSERT INTO accounts (id, username, username_key, password_hash, created_ms)"
            " VALUES (1, 'Ann', 'ann', 'h', 7), (2, 'Bo', 'bo', 'h', 8);"
            "INSERT INTO matches (id, map, mode, started_ms, ended_ms, tick_rate)"
            " VALUES (1, 'arena', 'ffa', 100, 200, 60);"
            "INSERT INTO match_players VALUES (1, 1, 3, 1, 3, 10, 4, 80, 20, 100, 1500, 1516),"
            " (1, 2, 1, 3, 1, 9, 2, 20, 80, 100, 1500, 1484);"
            "INSERT INTO player_stats (account_id, matches, wins, kills, rating)"
            " VALUES (1, 1, 1, 3, 1516), (2, 1, 0, 1, 1484);"
            "PRAGMA user_version = 2"),
        SQLITE_OK)
        << sqlite3_errmsg(raw.get());
  }
  auto store = must(open_store(path), "open a version-2 file");
  EXPECT_EQ(raw_integer(path, "PRAGMA user_version"), sqlite_schema_version());
  // The old match reads as what it was: a free-for-all that ended normally, no teams.
  EXPECT_EQ(raw_integer(path,
                        "SELECT COUNT(*) FROM matches WHERE id = 1 AND aborted = 0"
                        " AND red_score = 0 AND blue_score = 0"),
            1);
  EXPECT_EQ(raw_integer(path, "SELECT COUNT(*) FROM match_players WHERE team = 0"), 2);
  EXPECT_DOUBLE_EQ(must(store->player_stats(1), "Ann").rating, 1516);
  // And the new fields are written: an aborted team deathmatch next to it.
  MatchRecord tdm;
  tdm.map = "foundry";
  tdm.mode = "tdm";
  tdm.started_ms = 300;
  tdm.ended_ms = 400;
  tdm.aborted = true;
  tdm.team_scores = {4, 2};
  PlayerResult ann, bo;
  ann.account = 1;
  ann.team = kTeamRed;
  bo.account = 2;
  bo.team = kTeamBlue;
  tdm.players = {ann, bo};
  must(store->insert_match(tdm, {{1516, 1516, false}, {1484, 1484, false}}), "insert");
  EXPECT_EQ(raw_integer(path,
                        "SELECT COUNT(*) FROM matches WHERE aborted = 1 AND red_score = 4"
                        " AND blue_score = 2"),
            1);
  EXPECT_EQ(raw_integer(path,
                        "SELECT team FROM match_players WHERE match_id = 2 AND"
                        " account_id = 2"),
            kTeamBlue);
  EXPECT_EQ(must(store->player_stats(2), "Bo").matches, 2);
  // The constraints of the new columns hold.
  sqlite::Connection raw;
  ASSERT_EQ(sqlite::open(path, SQLITE_OPEN_READWRITE, raw), SQLITE_OK);
  EXPECT_NE(sqlite::exec(raw.get(), "UPDATE match_players SET team = 3"), SQLITE_OK);
  EXPECT_NE(sqlite::exec(raw.get(), "UPDATE matches SET aborted = 2"), SQLITE_OK);
}

TEST(MigrationTest, ReopeningIsIdempotent) {
  TempDir dir;
  const std::string path = dir.file("again.db");
  AccountId id = 0;
  {
    auto store = must(open_store(path), "first open");
    id = must(store->insert_account("alice", "alice", "h", 1), "insert");
  }
  const std::int64_t objects = raw_integer(path, "SELECT COUNT(*) FROM sqlite_schema");
  for (int i = 0; i < 3; ++i) {
    auto store = must(open_store(path), "reopen");
    EXPECT_EQ(must(store->account(id), "account").username, "alice");
  }
  EXPECT_EQ(raw_integer(path, "PRAGMA user_version"), sqlite_schema_version());
  EXPECT_EQ(raw_integer(path, "SELECT COUNT(*) FROM sqlite_schema"), objects);
  EXPECT_EQ(raw_integer(path, "SELECT COUNT(*) FROM accounts"), 1);
}

TEST(MigrationTest, ConcurrentFirstOpensMigrateOnce) {
  TempDir dir;
  const std::string path = dir.file("race.db");
  std::vector<std::thread> threads;
  std::vector<DbStatus> results(4);
  for (std::size_t i = 0; i < results.size(); ++i) {
    threads.emplace_back([&, i] {
      auto store = open_store(path);
      if (!store) results[i] = store.error();
    });
  }
  for (auto& t : threads) t.join();
  for (const DbStatus& s : results) RICOCHET_DB_EXPECT_OK(s);
  EXPECT_EQ(raw_integer(path, "PRAGMA user_version"), sqlite_schema_version());
}

TEST(MigrationTest, NewerSchemaIsRefusedAndTheFileLeftAlone) {
  TempDir dir;
  const std::string path = dir.file("future.db");
  const int newer = sqlite_schema_version() + 6;
  {
    sqlite::Connection raw;
    ASSERT_EQ(sqlite::open(path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, raw), SQLITE_OK);
    const std::string sql =
        "CREATE TABLE future_things (x); PRAGMA user_version = " + std::to_string(newer);
    ASSERT_EQ(sqlite::exec(raw.get(), sql.c_str()), SQLITE_OK) << sqlite3_errmsg(raw.get());
  }
  const std::string before = read_bytes(path);
  const auto opened = open_store(path);
  ASSERT_TRUE(fails_with(opened, DbErrorCode::SchemaTooNew));
  EXPECT_TRUE(mentions(opened.error(), path));
  EXPECT_TRUE(mentions(opened.error(), "schema version " + std::to_string(newer)));
  EXPECT_TRUE(mentions(opened.error(), "knows up to " + std::to_string(sqlite_schema_version())));
  EXPECT_TRUE(mentions(opened.error(), "upgrade Ricochet"));
  EXPECT_EQ(read_bytes(path), before);
  EXPECT_EQ(files_in(dir.path()), std::vector<std::string>{"future.db"});  // no -wal, no -shm
}

TEST(MigrationTest, NegativeSchemaVersionIsCorrupt) {
  TempDir dir;
  const std::string path = dir.file("negative.db");
  {
    sqlite::Connection raw;
    ASSERT_EQ(sqlite::open(path, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, raw), SQLITE_OK);
    ASSERT_EQ(sqlite::exec(raw.get(), "CREATE TABLE t (x); PRAGMA user_version = -3"), SQLITE_OK);
  }
  const auto opened = open_store(path);
  ASSERT_TRUE(fails_with(opened, DbErrorCode::CorruptDatabase));
  EXPECT_TRUE(mentions(opened.error(), path));
}

TEST(MigrationTest, GarbageFileIsCorrupt) {
  TempDir dir;
  const std::string path = dir.file("garbage.db");
  const std::string garbage(4096, static_cast<char>(0xAB));
  write_bytes(path, garbage);
  const auto opened = open_store(path);
  ASSERT_TRUE(fails_with(opened, DbErrorCode::CorruptDatabase));
  EXPECT_TRUE(mentions(opened.error(), path));
  EXPECT_EQ(read_bytes(path), garbage);
}

TEST(MigrationTest, TruncatedDatabaseIsCorrupt) {
  TempDir dir;
  const std::string path = dir.file("truncated.db");
  {
    auto store = must(open_store(path), "open");
    for (int i = 0; i < 300; ++i) {
      const std::string name = "player" + std::to_string(i);
      must(store->insert_account(name, name, std::string(100, 'h'), i), "insert");
    }
  }
  ASSERT_FALSE(fs::exists(path + "-wal")) << "closing should checkpoint and remove the WAL";
  const auto size = fs::file_size(path);
  ASSERT_GE(size, 8u * 4096u);
  fs::resize_file(path, size / 2);
  const auto opened = open_store(path);
  ASSERT_TRUE(fails_with(opened, DbErrorCode::CorruptDatabase));
  EXPECT_TRUE(mentions(opened.error(), path));
}

TEST(MigrationTest, DirectoryCannotBeOpened) {
  TempDir dir;
  const std::string path = dir.file("a-directory");
  fs::create_directory(path);
  const auto opened = open_store(path);
  ASSERT_TRUE(fails_with(opened, DbErrorCode::CannotOpen));
  EXPECT_TRUE(mentions(opened.error(), path));
}

TEST(MigrationTest, FileInMissingDirectoryCannotBeOpened) {
  TempDir dir;
  const std::string path = dir.file("missing/ricochet.db");
  const auto opened = open_store(path);
  ASSERT_TRUE(fails_with(opened, DbErrorCode::CannotOpen));
  EXPECT_TRUE(mentions(opened.error(), path));
  EXPECT_FALSE(fs::exists(dir.file("missing")));
}

TEST(MigrationTest, ReadOnlyFileCannotBeOpened) {
  if (geteuid() == 0) GTEST_SKIP() << "root can write a read-only file";
  TempDir dir;
  const std::string path = dir.file("read-only.db");
  must(open_store(path), "create");
  fs::permissions(path, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  const auto opened = open_store(path);
  ASSERT_TRUE(fails_with(opened, DbErrorCode::CannotOpen));
  EXPECT_TRUE(mentions(opened.error(), path));
}

TEST(MigrationTest, EmptyPathCannotBeOpened) {
  EXPECT_TRUE(fails_with(open_store(""), DbErrorCode::CannotOpen));
}

// --- connection settings, read on the store's own connection ---

sqlite3* g_opened = nullptr;

int remember_connection(sqlite3* db, const char**, const sqlite3_api_routines*) {
  g_opened = db;
  return SQLITE_OK;
}

/// Opens a store and hands back the sqlite3 handle it opened, caught with an auto-extension
/// (SQLite calls it for every connection opened in the process).
std::unique_ptr<Store> open_and_catch_connection(const SqliteOptions& options, sqlite3*& db) {
  const auto hook = reinterpret_cast<void (*)()>(&remember_connection);
  g_opened = nullptr;
  EXPECT_EQ(sqlite3_auto_extension(hook), SQLITE_OK);
  auto store = must(open_sqlite_store(options), "open");
  sqlite3_cancel_auto_extension(hook);
  db = g_opened;
  return store;
}

std::int64_t pragma(sqlite3* db, const char* sql) {
  std::int64_t value = -1;
  EXPECT_EQ(sqlite::single_integer(db, sql, value), SQLITE_OK) << sql;
  return value;
}

TEST(MigrationTest, ConnectionSettingsAreInEffect) {
  TempDir dir;
  SqliteOptions options;
  options.path = dir.file("settings.db");
  options.busy_timeout_ms = 1234;
  sqlite3* db = nullptr;
  auto store = open_and_catch_connection(options, db);
  ASSERT_NE(db, nullptr);
  EXPECT_EQ(pragma(db, "PRAGMA synchronous"), 1);  // NORMAL
  EXPECT_EQ(pragma(db, "PRAGMA foreign_keys"), 1);
  EXPECT_EQ(pragma(db, "PRAGMA busy_timeout"), 1234);
  std::string mode;
  ASSERT_EQ(sqlite::single_text(db, "PRAGMA journal_mode", mode), SQLITE_OK);
  EXPECT_EQ(mode, "wal");
  store.reset();

  // The journal mode is kept in the file: a fresh connection sees it too.
  sqlite::Connection raw;
  ASSERT_EQ(sqlite::open(options.path, SQLITE_OPEN_READONLY, raw), SQLITE_OK);
  ASSERT_EQ(sqlite::single_text(raw.get(), "PRAGMA journal_mode", mode), SQLITE_OK);
  EXPECT_EQ(mode, "wal");

  options.synchronous_full = true;
  store = open_and_catch_connection(options, db);
  ASSERT_NE(db, nullptr);
  EXPECT_EQ(pragma(db, "PRAGMA synchronous"), 2);  // FULL
}

/// A version-3 database on either backend, as that binary left it: two accounts and one match
/// they played, with their results and lifetime stats.
class Version3Test : public ::testing::TestWithParam<Backend> {
 protected:
  Version3Test() : db_(GetParam()) {
    if (db_.postgres()) {
      db_.exec(
          "CREATE TABLE schema_version (one_row BOOLEAN PRIMARY KEY DEFAULT TRUE"
          " CHECK (one_row), version INTEGER NOT NULL)");
      for (const Migration& m : postgres_migrations().first(3)) db_.exec(m.sql);
      db_.exec("INSERT INTO schema_version (version) VALUES (3)");
    } else {
      sqlite::Connection created;  // the file, empty
      if (sqlite::open(db_.url_or_path(), SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, created) !=
          SQLITE_OK)
        throw std::runtime_error("cannot create " + db_.url_or_path());
      for (const Migration& m : sqlite_migrations().first(3)) db_.exec(m.sql);
      db_.exec("PRAGMA user_version = 3");
    }
    db_.exec(
        "INSERT INTO accounts (username, username_key, password_hash, created_ms)"
        " VALUES ('Ann', 'ann', 'h', 7), ('Bo', 'bo', 'h', 8)");
    db_.exec(
        "INSERT INTO matches (map, mode, started_ms, ended_ms, tick_rate)"
        " VALUES ('arena', 'ffa', 100, 200, 60)");
    db_.exec(
        "INSERT INTO match_players (match_id, account_id, kills, deaths, score, shots, hits,"
        " damage_dealt, damage_taken, seconds_played, rating_before, rating_after)"
        " VALUES (1, 1, 3, 1, 3, 10, 4, 80, 20, 100, 1500, 1516),"
        " (1, 2, 1, 3, 1, 9, 2, 20, 80, 100, 1500, 1484)");
    db_.exec(
        "INSERT INTO player_stats (account_id, matches, wins, kills, rating)"
        " VALUES (1, 1, 1, 3, 1516), (2, 1, 0, 1, 1484)");
  }
  TestDatabase db_;
};

TEST_P(Version3Test, GainsMatchUuidsAndKeepsItsRows) {
  auto store = db_.open();
  const std::string version =
      db_.postgres() ? "SELECT version FROM schema_version" : "PRAGMA user_version";
  EXPECT_EQ(db_.raw_integer(version), sqlite_schema_version());  // the newest
  // The old match is kept, without a uuid.
  EXPECT_EQ(db_.raw_integer("SELECT COUNT(*) FROM matches WHERE id = 1 AND uuid IS NULL"), 1);
  EXPECT_EQ(db_.raw_integer("SELECT COUNT(*) FROM match_players"), 2);
  EXPECT_DOUBLE_EQ(must(store->player_stats(1), "Ann").rating, 1516);
  // A new one is written with its uuid, and written once.
  Matches matches(*store);
  MatchRecord next = match_of({result(1, 5), result(2, 3)});
  const RecordedMatch first = must(matches.record_match(next), "a new match");
  EXPECT_EQ(must(matches.record_match(next), "again").id, first.id);
  EXPECT_EQ(db_.query_one("SELECT uuid FROM matches WHERE id = " + std::to_string(first.id)),
            next.uuid);
  EXPECT_EQ(db_.raw_integer("SELECT COUNT(*) FROM matches"), 2);
  EXPECT_EQ(must(store->player_stats(1), "Ann").matches, 2);
  // The column holds uuids only, once each.
  EXPECT_THROW(db_.exec("UPDATE matches SET uuid = 'NOT-HEX' WHERE id = 1"), std::runtime_error);
  EXPECT_THROW(db_.exec("UPDATE matches SET uuid = '" + next.uuid + "' WHERE id = 1"),
               std::runtime_error);
}

INSTANTIATE_TEST_SUITE_P(Backends, Version3Test, kBackends, backend_name);

}  // namespace
}  // namespace ricochet::db::test::migration_test
