// What only the SQLite store has: a private file (mode 0600 for the database and its WAL) and
// the query plans of the leaderboard queries (EXPLAIN QUERY PLAN). The Store contract is tested
// on both backends in store_test.cpp.

#include <sys/stat.h>

#include <map>

#include "leaderboard_sql.h"
#include "sqlite_handle.h"
#include "store_fixture.h"

namespace ricochet::db::test::sqlite_store_test {
namespace {

using SqliteStoreTest = StoreTest;

TEST_P(SqliteStoreTest, TheDatabaseFilesAreTheOwnersAlone) {
  add("mode");  // a write: the -wal and -shm files exist now
  for (const std::string suffix : {"", "-wal", "-shm"}) {
    struct stat file {};
    ASSERT_EQ(::stat((db_.url_or_path() + suffix).c_str(), &file), 0) << suffix;
    EXPECT_EQ(file.st_mode & 0777, 0600u) << suffix;
  }
}

std::vector<std::string> query_plan(sqlite3* db, const std::string& sql) {
  sqlite::Statement explain;
  EXPECT_EQ(explain.prepare(db, "EXPLAIN QUERY PLAN " + sql), SQLITE_OK) << sqlite3_errmsg(db);
  sqlite::Query q(explain);
  std::vector<std::string> lines;
  while (q.step() == SQLITE_ROW) lines.push_back(q.text(3));
  return lines;
}

TEST_P(SqliteStoreTest, LeaderboardQueriesWalkTheirIndexes) {
  sqlite::Connection raw;
  ASSERT_EQ(sqlite::open(db_.url_or_path(), SQLITE_OPEN_READONLY, raw), SQLITE_OK);
  const std::map<LeaderboardKind, std::string> indexes = {
      {LeaderboardKind::Rating, "player_stats_by_rating"},
      {LeaderboardKind::Kills, "player_stats_by_kills"},
      {LeaderboardKind::WinRate, "player_stats_by_win_rate"}};
  for (const auto& [kind, index] : indexes) {
    SCOPED_TRACE(index);
    const auto top = query_plan(raw.get(), leaderboard_sql::top(kind));
    ASSERT_FALSE(top.empty());
    // Outer loop: player_stats in index order, then one account lookup per row.
    EXPECT_EQ(top[0], "SCAN s USING INDEX " + index);
    for (const std::string& line : top)
      EXPECT_EQ(line.find("TEMP B-TREE"), std::string::npos) << line;
    const auto count = query_plan(raw.get(), leaderboard_sql::count_better(kind));
    ASSERT_EQ(count.size(), 1u);
    EXPECT_EQ(count[0].rfind("SEARCH player_stats USING ", 0), 0u) << count[0];
    EXPECT_NE(count[0].find("INDEX " + index + " ("), std::string::npos) << count[0];
  }
}

INSTANTIATE_TEST_SUITE_P(Sqlite, SqliteStoreTest, ::testing::Values(Backend::Sqlite), backend_name);

}  // namespace
}  // namespace ricochet::db::test::sqlite_store_test
