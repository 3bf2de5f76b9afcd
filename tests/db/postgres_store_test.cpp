// What only the PostgreSQL store has, on a real cluster (postgres_cluster.h): the schema version
// row and its migrations numbered like SQLite's, a newer schema refused, servers that open a new
// database at once, a server that cannot be reached or refuses us, a connection lost mid-run,
// and the query plans of the leaderboard queries (EXPLAIN). The Store contract is tested on both
// backends in store_test.cpp.

#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <map>
#include <thread>

#include "leaderboard_sql.h"
#include "migrations.h"
#include "postgres_migrations.h"
#include "store_fixture.h"

namespace ricochet::db::test::postgres_store_test {
namespace {

using PostgresStoreTest = StoreTest;

TEST(PostgresMigrations, AreNumberedLikeSqlites) {
  const auto pg = postgres_migrations();
  const auto lite = sqlite_migrations();
  ASSERT_EQ(pg.size(), lite.size());
  for (std::size_t i = 0; i < pg.size(); ++i) {
    EXPECT_EQ(pg[i].version, static_cast<int>(i) + 1);
    EXPECT_EQ(pg[i].version, lite[i].version);
    EXPECT_STREQ(pg[i].summary, lite[i].summary);
  }
  EXPECT_EQ(postgres_schema_version(), sqlite_schema_version());
}

TEST_P(PostgresStoreTest, ANewDatabaseEndsAtTheCurrentVersionAndReopeningChangesNothing) {
  EXPECT_EQ(raw_integer("SELECT version FROM schema_version"), postgres_schema_version());
  add("alice");
  reopen();
  EXPECT_EQ(raw_integer("SELECT COUNT(*) FROM schema_version"), 1);
  EXPECT_EQ(rows("accounts"), 1);
}

TEST_P(PostgresStoreTest, ANewerSchemaIsRefusedAndLeftAlone) {
  store_.reset();
  const int newer = postgres_schema_version() + 1;
  db_.exec("UPDATE schema_version SET version = " + std::to_string(newer));
  const auto opened = db_.try_open();
  ASSERT_TRUE(fails_with(opened, DbErrorCode::SchemaTooNew));
  const std::string& message = opened.error().message;
  EXPECT_NE(message.find(db_.where()), std::string::npos) << message;
  EXPECT_NE(message.find("version " + std::to_string(newer)), std::string::npos) << message;
  EXPECT_NE(message.find("up to " + std::to_string(postgres_schema_version())), std::string::npos)
      << message;
  EXPECT_EQ(raw_integer("SELECT version FROM schema_version"), newer);
}

TEST(PostgresStore, ServersOpeningANewDatabaseAtOnceMigrateItOnce) {
  const TestDatabase db(Backend::Postgres);
  std::vector<std::thread> servers;
  std::vector<DbStatus> opened(4);
  for (std::size_t i = 0; i < opened.size(); ++i) {
    servers.emplace_back([&, i] {
      auto store = db.try_open();
      if (!store.ok()) opened[i] = store.error();
    });
  }
  for (std::thread& t : servers) t.join();
  for (const DbStatus& s : opened) RICOCHET_DB_EXPECT_OK(s);
  EXPECT_EQ(db.raw_integer("SELECT version FROM schema_version"), postgres_schema_version());
}

TEST(PostgresStore, AServerThatCannotBeReachedIsUnavailableAndItsPasswordIsNotShown) {
  // A port bound but not listening: connections to it are refused while the test holds it.
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof address;
  ASSERT_EQ(bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  ASSERT_EQ(getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length), 0);
  const int port = ntohs(address.sin_port);
  const std::string url = "postgresql://ricochet:hunter2@127.0.0.1:" + std::to_string(port) + "/x";
  const auto opened = open_store({.url_or_path = url});
  ASSERT_TRUE(fails_with(opened, DbErrorCode::Unavailable));
  EXPECT_EQ(opened.error().message.find("hunter2"), std::string::npos) << opened.error().message;
  EXPECT_NE(opened.error().message.find("127.0.0.1:" + std::to_string(port)), std::string::npos)
      << opened.error().message;
  EXPECT_NE(opened.error().message.find("retry later"), std::string::npos);
  close(fd);
}

TEST(PostgresStore, AMissingDatabaseCannotBeOpened) {
  const std::string url = ricochet::test::PostgresCluster::shared().url("no_such_database");
  const auto opened = open_store({.url_or_path = url});
  ASSERT_TRUE(fails_with(opened, DbErrorCode::CannotOpen));
  EXPECT_NE(opened.error().message.find("no_such_database"), std::string::npos);
}

TEST(PostgresStore, OnlyPostgresUrlsSelectPostgres) {
  EXPECT_TRUE(is_postgres_url("postgresql://u@h/db"));
  EXPECT_TRUE(is_postgres_url("postgres://u@h/db"));
  EXPECT_FALSE(is_postgres_url("data/ricochet.db"));
  EXPECT_FALSE(is_postgres_url("postgresql.db"));
  EXPECT_FALSE(is_postgres_url(""));
}

TEST_P(PostgresStoreTest, ALostConnectionIsUnavailableAndTheNextCallReconnects) {
  const AccountId a = add("alice");
  // What a server restart or a network cut does to the store's connection.
  db_.exec(
      "SELECT pg_terminate_backend(pid) FROM pg_stat_activity"
      " WHERE datname = current_database() AND pid <> pg_backend_pid()");
  const auto lost = store_->account(a);
  ASSERT_TRUE(fails_with(lost, DbErrorCode::Unavailable));
  EXPECT_NE(lost.error().message.find("retry later"), std::string::npos) << lost.error().message;
  // Reconnected, with its statements prepared and its lock timeout set again.
  EXPECT_EQ(must(store_->account(a), "after reconnecting").username, "alice");
  must(store_->insert_match(match_of({result(a, 1)}), {{1500, 1500, true}}), "a write");
  EXPECT_EQ(must(store_->match_count(), "count"), 1);
}

/// EXPLAIN's text for `sql` with its parameters spelled in, on the test's database.
std::string query_plan(const TestDatabase& db, std::string sql,
                       const std::vector<std::string>& params) {
  for (std::size_t i = params.size(); i > 0; --i) {
    const std::string name = "$" + std::to_string(i);
    for (std::size_t at; (at = sql.find(name)) != std::string::npos;)
      sql.replace(at, name.size(), params[i - 1]);
  }
  postgres::Connection raw = db.connect();
  postgres::Result r = postgres::exec(raw.get(), ("EXPLAIN " + sql).c_str());
  EXPECT_TRUE(r.ok()) << sql << ": " << PQresultErrorMessage(r.get());
  std::string plan;
  for (int row = 0; row < r.rows(); ++row) plan += r.text(row, 0) + "\n";
  return plan;
}

TEST_P(PostgresStoreTest, LeaderboardQueriesWalkTheirIndexes) {
  // 20 000 players of 1..400 matches, so that the planner has a reason to choose.
  db_.exec(
      "INSERT INTO accounts (username, username_key, password_hash, created_ms)"
      " SELECT 'p' || i, 'p' || i, 'h', 0 FROM generate_series(1, 20000) AS i;"
      "INSERT INTO player_stats (account_id, matches, wins, kills, rating)"
      " SELECT id, 1 + id % 400, (id * 7) % (1 + id % 400), id % 997, 1000 + (id * 37) % 1000"
      " FROM accounts;"
      "ANALYZE");
  struct Board {
    LeaderboardKind kind;
    std::string index;
    std::vector<std::string> top_params, count_params;
  };
  const Board boards[] = {
      {LeaderboardKind::Rating, "player_stats_by_rating", {"10"}, {"1990"}},
      {LeaderboardKind::Kills, "player_stats_by_kills", {"10"}, {"990"}},
      {LeaderboardKind::WinRate, "player_stats_by_win_rate", {"10", "100"}, {"0.99", "100"}}};
  for (const Board& b : boards) {
    SCOPED_TRACE(b.index);
    const std::string top = query_plan(db_, leaderboard_sql::postgres_top(b.kind), b.top_params);
    EXPECT_NE(top.find("Index Scan using " + b.index), std::string::npos) << top;
    EXPECT_EQ(top.find("Sort"), std::string::npos) << top;
    const std::string count =
        query_plan(db_, leaderboard_sql::postgres_count_better(b.kind), b.count_params);
    EXPECT_NE(count.find(b.index), std::string::npos) << count;
    EXPECT_EQ(count.find("Seq Scan"), std::string::npos) << count;
  }
}

INSTANTIATE_TEST_SUITE_P(Postgres, PostgresStoreTest, ::testing::Values(Backend::Postgres),
                         backend_name);

}  // namespace
}  // namespace ricochet::db::test::postgres_store_test
