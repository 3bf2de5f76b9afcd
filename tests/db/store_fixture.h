#pragma once
/// A SQLite store on a fresh file per test, a raw connection to look at what was written, and
/// match records to feed it.

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "db_test_util.h"
#include "ricochet/db/store.h"

namespace ricochet::db::test {

inline PlayerResult result(AccountId account, std::int32_t score, std::int32_t kills = 0) {
  PlayerResult p;
  p.account = account;
  p.score = score;
  p.kills = kills;
  p.deaths = 1;
  p.shots = 10;
  p.hits = 4;
  p.damage_dealt = 120.5;
  p.damage_taken = 80.25;
  p.seconds_played = 300;
  return p;
}

inline MatchRecord match_of(std::vector<PlayerResult> players) {
  MatchRecord m;
  m.map = "foundry";
  m.mode = "ffa";
  m.started_ms = 1'000'000;
  m.ended_ms = 1'300'000;
  m.tick_rate = 60;
  m.players = std::move(players);
  return m;
}

class StoreTest : public ::testing::Test {
 protected:
  StoreTest() : path_(dir_.file("ricochet.db")) { reopen(); }

  void reopen() {
    store_.reset();
    SqliteOptions options;
    options.path = path_;
    store_ = must(open_sqlite_store(options), "open_sqlite_store");
  }

  AccountId add(const std::string& name) {
    std::string key = name;
    std::transform(key.begin(), key.end(), key.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return must(store_->insert_account(name, key, "hash-of-" + name, 1000), "insert_account");
  }

  /// The first column of the first row of `sql`, through a separate raw connection.
  std::int64_t raw_integer(const std::string& sql) {
    sqlite::Connection raw;
    EXPECT_EQ(sqlite::open(path_, SQLITE_OPEN_READONLY, raw), SQLITE_OK);
    std::int64_t value = -1;
    EXPECT_EQ(sqlite::single_integer(raw.get(), sql, value), SQLITE_OK)
        << sql << ": " << sqlite3_errmsg(raw.get());
    return value;
  }
  std::int64_t rows(const std::string& table) {
    return raw_integer("SELECT COUNT(*) FROM " + table);
  }

  TempDir dir_;
  std::string path_;
  std::unique_ptr<Store> store_;
};

}  // namespace ricochet::db::test
