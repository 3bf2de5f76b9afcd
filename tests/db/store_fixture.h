#pragma once
/// A store on a fresh database per test, on the backend of the test's parameter (SQLite or
/// PostgreSQL, test_database.h), a raw connection to look at what was written, and match records
/// to feed it.

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "db_test_util.h"
#include "ricochet/db/matches.h"
#include "ricochet/db/store.h"
#include "test_database.h"

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
  m.uuid = new_match_uuid();
  m.map = "foundry";
  m.mode = "ffa";
  m.started_ms = 1'000'000;
  m.ended_ms = 1'300'000;
  m.tick_rate = 60;
  m.players = std::move(players);
  return m;
}

class StoreTest : public ::testing::TestWithParam<Backend> {
 protected:
  StoreTest() : db_(GetParam()) { reopen(); }

  void reopen() {
    store_.reset();
    store_ = db_.open();
  }

  AccountId add(const std::string& name) {
    std::string key = name;
    std::transform(key.begin(), key.end(), key.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return must(store_->insert_account(name, key, "hash-of-" + name, 1000), "insert_account");
  }

  /// The first column of the first row of `sql`, through a separate raw connection.
  std::int64_t raw_integer(const std::string& sql) { return db_.raw_integer(sql); }
  std::int64_t rows(const std::string& table) {
    return raw_integer("SELECT COUNT(*) FROM " + table);
  }

  TestDatabase db_;
  std::unique_ptr<Store> store_;
};

}  // namespace ricochet::db::test
