// The SQLite store through the Store interface, on real files: accounts, sessions, matches with
// stats and Elo ratings, leaderboards and ranks, atomicity of record_match, persistence across
// reopening, lock timeouts, and the query plans of the leaderboard queries. A second, raw SQLite
// connection looks at what was actually written.

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "db_test_util.h"
#include "leaderboard_sql.h"
#include "ricochet/db/rating.h"
#include "ricochet/db/store.h"
#include "sqlite_handle.h"

namespace ricochet::db::test {
namespace {

std::string token_hash(char seed) {
  std::string hash(32, '\0');
  for (std::size_t i = 0; i < hash.size(); ++i) hash[i] = static_cast<char>(seed * 31 + i);
  hash[5] = '\0';  // binary data: an embedded zero must survive
  return hash;
}

PlayerResult result(AccountId account, std::int32_t score, std::int32_t kills = 0) {
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

MatchRecord match_of(std::vector<PlayerResult> players) {
  MatchRecord m;
  m.map = "foundry";
  m.mode = "ffa";
  m.started_ms = 1'000'000;
  m.ended_ms = 1'300'000;
  m.tick_rate = 60;
  m.players = std::move(players);
  return m;
}

class SqliteStoreTest : public ::testing::Test {
 protected:
  SqliteStoreTest() : path_(dir_.file("ricochet.db")) { reopen(); }

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

// --- accounts ---

TEST_F(SqliteStoreTest, InsertsAndFindsAccounts) {
  const AccountId alice = add("Alice");
  const AccountId bob = add("bob");
  EXPECT_NE(alice, bob);

  const auto found = must(store_->find_account_by_key("alice"), "find");
  ASSERT_TRUE(found.has_value());
  EXPECT_EQ(found->account.id, alice);
  EXPECT_EQ(found->account.username, "Alice");  // case kept
  EXPECT_EQ(found->account.created_ms, 1000);
  EXPECT_FALSE(found->account.last_login_ms.has_value());
  EXPECT_FALSE(found->account.banned);
  EXPECT_EQ(found->password_hash, "hash-of-Alice");
  EXPECT_FALSE(must(store_->find_account_by_key("Alice"), "find by unlowered key").has_value());
  EXPECT_FALSE(must(store_->find_account_by_key("carol"), "find unknown").has_value());

  const Account a = must(store_->account(bob), "account");
  EXPECT_EQ(a.id, bob);
  EXPECT_EQ(a.username, "bob");
  EXPECT_TRUE(fails_with(store_->account(bob + 100), DbErrorCode::UnknownAccount));
}

TEST_F(SqliteStoreTest, DuplicateUsernameKeyIsRefused) {
  add("Alice");
  const auto again = store_->insert_account("ALICE", "alice", "h", 2000);
  ASSERT_TRUE(fails_with(again, DbErrorCode::DuplicateUsername));
  EXPECT_NE(again.error().message.find("ALICE"), std::string::npos) << again.error().message;
  EXPECT_EQ(rows("accounts"), 1);
}

TEST_F(SqliteStoreTest, UpdatesAccountFields) {
  const AccountId id = add("alice");
  RICOCHET_DB_ASSERT_OK(store_->set_password_hash(id, "new-hash"));
  RICOCHET_DB_ASSERT_OK(store_->set_banned(id, true));
  RICOCHET_DB_ASSERT_OK(store_->set_last_login(id, 5555));
  auto found = must(store_->find_account_by_key("alice"), "find");
  ASSERT_TRUE(found.has_value());
  EXPECT_EQ(found->password_hash, "new-hash");
  EXPECT_TRUE(found->account.banned);
  EXPECT_EQ(found->account.last_login_ms, 5555);

  RICOCHET_DB_ASSERT_OK(store_->set_banned(id, false));
  EXPECT_FALSE(must(store_->account(id), "account").banned);

  EXPECT_TRUE(fails_with(store_->set_password_hash(id + 1, "x"), DbErrorCode::UnknownAccount));
  EXPECT_TRUE(fails_with(store_->set_banned(id + 1, true), DbErrorCode::UnknownAccount));
  EXPECT_TRUE(fails_with(store_->set_last_login(id + 1, 1), DbErrorCode::UnknownAccount));
}

// --- sessions ---

TEST_F(SqliteStoreTest, SessionLifecycle) {
  const AccountId id = add("alice");
  const std::string hash = token_hash(1);
  RICOCHET_DB_ASSERT_OK(store_->insert_session(hash, id, 100, 900));
  const auto row = must(store_->find_session(hash), "find_session");
  ASSERT_TRUE(row.has_value());
  EXPECT_EQ(row->account, id);
  EXPECT_EQ(row->created_ms, 100);
  EXPECT_EQ(row->expires_ms, 900);
  EXPECT_FALSE(must(store_->find_session(token_hash(2)), "find other").has_value());
  // A hash that differs only after the embedded zero byte is another session.
  std::string other = hash;
  other[20] = static_cast<char>(other[20] + 1);
  EXPECT_FALSE(must(store_->find_session(other), "find after zero byte").has_value());

  RICOCHET_DB_ASSERT_OK(store_->delete_session(hash));
  EXPECT_FALSE(must(store_->find_session(hash), "find deleted").has_value());
  RICOCHET_DB_EXPECT_OK(store_->delete_session(hash));  // deleting twice is harmless
}

TEST_F(SqliteStoreTest, SessionRejectsBadHashAndUnknownAccount) {
  const AccountId id = add("alice");
  EXPECT_TRUE(fails_with(store_->insert_session(std::string(31, 'x'), id, 1, 2),
                         DbErrorCode::UnknownSession));
  EXPECT_TRUE(
      fails_with(store_->insert_session(token_hash(1), id + 1, 1, 2), DbErrorCode::UnknownAccount));
  EXPECT_FALSE(must(store_->find_session("short"), "find short").has_value());
  RICOCHET_DB_EXPECT_OK(store_->delete_session("short"));
  EXPECT_EQ(rows("sessions"), 0);
}

TEST_F(SqliteStoreTest, DeletesSessionsOfOneAccount) {
  const AccountId alice = add("alice");
  const AccountId bob = add("bob");
  RICOCHET_DB_ASSERT_OK(store_->insert_session(token_hash(1), alice, 0, 1000));
  RICOCHET_DB_ASSERT_OK(store_->insert_session(token_hash(2), alice, 0, 1000));
  RICOCHET_DB_ASSERT_OK(store_->insert_session(token_hash(3), bob, 0, 1000));
  RICOCHET_DB_ASSERT_OK(store_->delete_sessions_of(alice));
  EXPECT_FALSE(must(store_->find_session(token_hash(1)), "1").has_value());
  EXPECT_FALSE(must(store_->find_session(token_hash(2)), "2").has_value());
  EXPECT_TRUE(must(store_->find_session(token_hash(3)), "3").has_value());
}

TEST_F(SqliteStoreTest, DeletesExpiredSessions) {
  const AccountId id = add("alice");
  RICOCHET_DB_ASSERT_OK(store_->insert_session(token_hash(1), id, 0, 100));
  RICOCHET_DB_ASSERT_OK(store_->insert_session(token_hash(2), id, 0, 200));
  RICOCHET_DB_ASSERT_OK(store_->insert_session(token_hash(3), id, 0, 300));
  EXPECT_EQ(must(store_->delete_expired_sessions(200), "expire at 200"), 1);  // before now only
  EXPECT_FALSE(must(store_->find_session(token_hash(1)), "1").has_value());
  EXPECT_TRUE(must(store_->find_session(token_hash(2)), "2").has_value());
  EXPECT_EQ(must(store_->delete_expired_sessions(200), "again"), 0);
  EXPECT_EQ(must(store_->delete_expired_sessions(10'000), "all"), 2);
  EXPECT_EQ(rows("sessions"), 0);
}

// --- matches and stats ---

TEST_F(SqliteStoreTest, RecordMatchWritesMatchPlayersStatsAndRatings) {
  const AccountId winner = add("alice");
  const AccountId loser = add("bob");
  const MatchId id =
      must(store_->record_match(match_of({result(winner, 10, 3), result(loser, 5, 1)})), "record");
  EXPECT_EQ(must(store_->match_count(), "count"), 1);
  EXPECT_EQ(raw_integer("SELECT COUNT(*) FROM matches WHERE id = " + std::to_string(id) +
                        " AND map = 'foundry' AND mode = 'ffa' AND started_ms = 1000000"
                        " AND ended_ms = 1300000 AND tick_rate = 60"),
            1);
  EXPECT_EQ(rows("match_players"), 2);

  // Elo between equals: expected 0.5 each, K = 32, so the winner gains 16 and the loser loses 16.
  const PlayerStats w = must(store_->player_stats(winner), "winner stats");
  EXPECT_EQ(w.username, "alice");
  EXPECT_EQ(w.matches, 1);
  EXPECT_EQ(w.wins, 1);
  EXPECT_EQ(w.kills, 3);
  EXPECT_EQ(w.deaths, 1);
  EXPECT_EQ(w.score, 10);
  EXPECT_EQ(w.shots, 10);
  EXPECT_EQ(w.hits, 4);
  EXPECT_DOUBLE_EQ(w.damage_dealt, 120.5);
  EXPECT_DOUBLE_EQ(w.damage_taken, 80.25);
  EXPECT_DOUBLE_EQ(w.seconds_played, 300);
  EXPECT_DOUBLE_EQ(w.rating, 1516);
  const PlayerStats l = must(store_->player_stats(loser), "loser stats");
  EXPECT_EQ(l.matches, 1);
  EXPECT_EQ(l.wins, 0);
  EXPECT_DOUBLE_EQ(l.rating, 1484);

  EXPECT_EQ(raw_integer(
                "SELECT COUNT(*) FROM match_players WHERE account_id = " + std::to_string(winner) +
                " AND rating_before = 1500 AND rating_after = 1516 AND kills = 3"),
            1);
  EXPECT_EQ(
      raw_integer("SELECT COUNT(*) FROM match_players WHERE account_id = " + std::to_string(loser) +
                  " AND rating_before = 1500 AND rating_after = 1484"),
      1);
}

TEST_F(SqliteStoreTest, TiedTopScoresAllWin) {
  const AccountId a = add("a"), b = add("b"), c = add("c");
  must(store_->record_match(match_of({result(a, 7), result(b, 7), result(c, 3)})), "record");
  const PlayerStats sa = must(store_->player_stats(a), "a");
  const PlayerStats sb = must(store_->player_stats(b), "b");
  const PlayerStats sc = must(store_->player_stats(c), "c");
  EXPECT_EQ(sa.wins, 1);
  EXPECT_EQ(sb.wins, 1);
  EXPECT_EQ(sc.wins, 0);
  // a and b drew each other and both beat c: +8 each (K / (N - 1) = 16 per duel), c -16.
  EXPECT_DOUBLE_EQ(sa.rating, 1508);
  EXPECT_DOUBLE_EQ(sb.rating, 1508);
  EXPECT_DOUBLE_EQ(sc.rating, 1484);
}

TEST_F(SqliteStoreTest, StatsAccumulateAndRatingsCarryOver) {
  const AccountId a = add("a"), b = add("b");
  must(store_->record_match(match_of({result(a, 10, 2), result(b, 5, 1)})), "first");
  must(store_->record_match(match_of({result(a, 1, 4), result(b, 9, 6)})), "second");
  const std::vector<double> expected = updated_ratings({{1516, 1}, {1484, 9}});
  const PlayerStats sa = must(store_->player_stats(a), "a");
  const PlayerStats sb = must(store_->player_stats(b), "b");
  EXPECT_EQ(sa.matches, 2);
  EXPECT_EQ(sa.wins, 1);
  EXPECT_EQ(sa.kills, 6);
  EXPECT_EQ(sa.score, 11);
  EXPECT_DOUBLE_EQ(sa.damage_dealt, 241);
  EXPECT_DOUBLE_EQ(sa.seconds_played, 600);
  EXPECT_EQ(sb.wins, 1);
  EXPECT_EQ(sb.kills, 7);
  EXPECT_DOUBLE_EQ(sa.rating, expected[0]);
  EXPECT_DOUBLE_EQ(sb.rating, expected[1]);
  EXPECT_DOUBLE_EQ(sa.rating + sb.rating, 3000);  // Elo conserves the total
  EXPECT_EQ(must(store_->match_count(), "count"), 2);
}

TEST_F(SqliteStoreTest, PlayerStatsOfAnAccountThatNeverPlayed) {
  const AccountId id = add("Newbie");
  const PlayerStats s = must(store_->player_stats(id), "stats");
  EXPECT_EQ(s.account, id);
  EXPECT_EQ(s.username, "Newbie");
  EXPECT_EQ(s.matches, 0);
  EXPECT_EQ(s.wins, 0);
  EXPECT_EQ(s.kills, 0);
  EXPECT_EQ(s.damage_dealt, 0);
  EXPECT_EQ(s.rating, kInitialRating);
  EXPECT_TRUE(fails_with(store_->player_stats(id + 1), DbErrorCode::UnknownAccount));
}

TEST_F(SqliteStoreTest, InvalidMatchesWriteNothing) {
  const AccountId a = add("a"), b = add("b");
  const AccountId unknown = b + 1000;
  const auto with = [&](auto change) {
    MatchRecord m = match_of({result(a, 5), result(b, 3)});
    change(m);
    return m;
  };
  const std::vector<std::pair<std::string, MatchRecord>> cases = {
      {"unknown account", with([&](MatchRecord& m) { m.players.push_back(result(unknown, 1)); })},
      {"listed twice", with([&](MatchRecord& m) { m.players.push_back(result(a, 1)); })},
      {"no players", with([](MatchRecord& m) { m.players.clear(); })},
      {"empty map", with([](MatchRecord& m) { m.map.clear(); })},
      {"long mode", with([](MatchRecord& m) { m.mode = std::string(65, 'm'); })},
      {"ends before start", with([](MatchRecord& m) { m.ended_ms = m.started_ms - 1; })},
      {"tick rate 0", with([](MatchRecord& m) { m.tick_rate = 0; })},
      {"tick rate 1001", with([](MatchRecord& m) { m.tick_rate = 1001; })},
      {"negative kills", with([](MatchRecord& m) { m.players[1].kills = -1; })},
      {"negative hits", with([](MatchRecord& m) { m.players[0].hits = -3; })},
      {"NaN damage", with([](MatchRecord& m) {
         m.players[0].damage_dealt = std::numeric_limits<double>::quiet_NaN();
       })},
      {"infinite time", with([](MatchRecord& m) {
         m.players[1].seconds_played = std::numeric_limits<double>::infinity();
       })},
      {"negative damage", with([](MatchRecord& m) { m.players[1].damage_taken = -0.5; })},
  };
  for (const auto& [name, match] : cases) {
    SCOPED_TRACE(name);
    EXPECT_TRUE(fails_with(store_->record_match(match), DbErrorCode::InvalidMatch));
  }
  const auto unknown_error = store_->record_match(cases[0].second).error().message;
  EXPECT_NE(unknown_error.find(std::to_string(unknown)), std::string::npos) << unknown_error;
  const auto twice_error = store_->record_match(cases[1].second).error().message;
  EXPECT_NE(twice_error.find("account " + std::to_string(a)), std::string::npos) << twice_error;

  EXPECT_EQ(rows("matches"), 0);
  EXPECT_EQ(rows("match_players"), 0);
  EXPECT_EQ(rows("player_stats"), 0);
  EXPECT_EQ(must(store_->player_stats(a), "a").rating, kInitialRating);
  // The store still works after the refusals.
  must(store_->record_match(match_of({result(a, 5), result(b, 3)})), "valid match");
  EXPECT_EQ(rows("match_players"), 2);
}

TEST_F(SqliteStoreTest, FailureHalfWayRollsBackTheWholeMatch) {
  const AccountId a = add("a"), b = add("b"), c = add("c");
  must(store_->record_match(match_of({result(a, 5), result(b, 3)})), "first match");
  // Make the third player's stats update fail, after the match and its players are written.
  inject_failure(path_, "BEFORE INSERT ON player_stats WHEN NEW.account_id = " + std::to_string(c));
  const auto failed = store_->record_match(match_of({result(a, 1), result(b, 2), result(c, 3)}));
  ASSERT_TRUE(fails_with(failed, DbErrorCode::Storage));
  EXPECT_NE(failed.error().message.find("injected failure"), std::string::npos)
      << failed.error().message;
  EXPECT_NE(failed.error().message.find(path_), std::string::npos) << failed.error().message;
  EXPECT_EQ(rows("matches"), 1);
  EXPECT_EQ(rows("match_players"), 2);
  EXPECT_EQ(raw_integer("SELECT SUM(matches) FROM player_stats"), 2);
  EXPECT_DOUBLE_EQ(must(store_->player_stats(a), "a").rating, 1516);
}

TEST_F(SqliteStoreTest, WriteLockHeldElsewhereIsBusy) {
  store_.reset();
  SqliteOptions options;
  options.path = path_;
  options.busy_timeout_ms = 50;
  store_ = must(open_sqlite_store(options), "open with a short timeout");
  const AccountId a = add("a");

  sqlite::Connection other;
  ASSERT_EQ(sqlite::open(path_, SQLITE_OPEN_READWRITE, other), SQLITE_OK);
  ASSERT_EQ(sqlite::exec(other.get(), "BEGIN IMMEDIATE"), SQLITE_OK);
  const auto blocked = store_->insert_account("b", "b", "h", 1);
  EXPECT_TRUE(fails_with(blocked, DbErrorCode::Busy));
  EXPECT_TRUE(fails_with(store_->record_match(match_of({result(a, 1)})), DbErrorCode::Busy));
  EXPECT_TRUE(must(store_->account(a), "reads go on under WAL").id == a);
  ASSERT_EQ(sqlite::exec(other.get(), "COMMIT"), SQLITE_OK);
  must(store_->insert_account("b", "b", "h", 1), "after the lock is released");
}

TEST_F(SqliteStoreTest, DataSurvivesCloseAndReopen) {
  const AccountId a = add("alice"), b = add("bob");
  RICOCHET_DB_ASSERT_OK(store_->insert_session(token_hash(7), a, 10, 20));
  must(store_->record_match(match_of({result(a, 10), result(b, 5)})), "record");
  reopen();
  EXPECT_EQ(must(store_->account(b), "bob").username, "bob");
  EXPECT_TRUE(must(store_->find_session(token_hash(7)), "session").has_value());
  EXPECT_EQ(must(store_->match_count(), "count"), 1);
  EXPECT_DOUBLE_EQ(must(store_->player_stats(a), "alice").rating, 1516);
  EXPECT_TRUE(
      fails_with(store_->insert_account("Alice", "alice", "h", 0), DbErrorCode::DuplicateUsername));
}

// --- leaderboards ---

class LeaderboardTest : public SqliteStoreTest {
 protected:
  void duel(AccountId winner, AccountId loser, std::int32_t winner_kills = 0) {
    must(store_->record_match(match_of({result(winner, 10, winner_kills), result(loser, 5)})),
         "duel");
  }
  void draw(AccountId x, AccountId y) {
    must(store_->record_match(match_of({result(x, 5), result(y, 5)})), "draw");
  }
  std::vector<LeaderboardEntry> board(LeaderboardKind kind, int limit = 100, int min_matches = 1) {
    return must(store_->leaderboard(kind, limit, min_matches), "leaderboard");
  }
};

TEST_F(LeaderboardTest, RatingBoardIsBestFirstAndTiesShareRank) {
  const AccountId a = add("a"), b = add("b"), c = add("c"), d = add("d"), idle = add("idle");
  duel(c, d);  // c 1516, d 1484
  duel(a, b);  // a 1516, b 1484
  const auto entries = board(LeaderboardKind::Rating);
  ASSERT_EQ(entries.size(), 4u);  // idle never played
  const std::vector<std::pair<AccountId, std::int64_t>> expected = {{a, 1}, {c, 1}, {b, 3}, {d, 3}};
  for (std::size_t i = 0; i < expected.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(entries[i].account, expected[i].first);
    EXPECT_EQ(entries[i].rank, expected[i].second);
    EXPECT_EQ(entries[i].matches, 1);
  }
  EXPECT_EQ(entries[0].username, "a");
  EXPECT_DOUBLE_EQ(entries[0].value, 1516);
  EXPECT_DOUBLE_EQ(entries[3].value, 1484);
  EXPECT_EQ(board(LeaderboardKind::Rating, 3).size(), 3u);
  EXPECT_TRUE(board(LeaderboardKind::Rating, 0).empty());
  EXPECT_TRUE(board(LeaderboardKind::Rating, -1).empty());

  const auto rank_d = must(store_->rank_of(d, LeaderboardKind::Rating, 1), "rank d");
  ASSERT_TRUE(rank_d.has_value());
  EXPECT_EQ(rank_d->rank, 3);
  EXPECT_EQ(rank_d->username, "d");
  EXPECT_DOUBLE_EQ(rank_d->value, 1484);
  EXPECT_FALSE(must(store_->rank_of(idle, LeaderboardKind::Rating, 1), "idle").has_value());
  EXPECT_TRUE(fails_with(store_->rank_of(idle + 1, LeaderboardKind::Rating, 1),
                         DbErrorCode::UnknownAccount));
}

TEST_F(LeaderboardTest, KillsBoard) {
  const AccountId a = add("a"), b = add("b"), c = add("c"), idle = add("idle");
  duel(a, b, 4);
  duel(c, b, 9);
  duel(b, a, 0);  // b's kills stay 0
  must(store_->record_match(match_of({result(b, 1, 4), result(c, 0, 0)})), "b gets 4 kills");
  const auto entries = board(LeaderboardKind::Kills);
  ASSERT_EQ(entries.size(), 3u);
  EXPECT_EQ(entries[0].account, c);
  EXPECT_EQ(entries[0].value, 9);
  EXPECT_EQ(entries[0].rank, 1);
  EXPECT_EQ(entries[1].account, a);
  EXPECT_EQ(entries[1].rank, 2);
  EXPECT_EQ(entries[2].account, b);
  EXPECT_EQ(entries[2].rank, 2);  // 4 kills each
  EXPECT_EQ(entries[2].matches, 4);
  EXPECT_EQ(must(store_->rank_of(b, LeaderboardKind::Kills, 1), "b")->rank, 2);
  EXPECT_FALSE(must(store_->rank_of(idle, LeaderboardKind::Kills, 1), "idle").has_value());
}

TEST_F(LeaderboardTest, WinRateHonoursMinimumMatches) {
  const AccountId p1 = add("p1"), p2 = add("p2"), p3 = add("p3"), p4 = add("p4"), p5 = add("p5"),
                  p6 = add("p6");
  duel(p1, p2);
  duel(p2, p1);  // p1 and p2: 1 of 2
  duel(p3, p4);
  draw(p3, p4);  // p3 2 of 2, p4 1 of 2 (a draw at the top score is a win)
  duel(p5, p6);  // p5 1 of 1, p6 0 of 1

  auto entries = board(LeaderboardKind::WinRate, 100, 1);
  std::vector<std::pair<AccountId, std::int64_t>> got;
  for (const auto& e : entries) got.emplace_back(e.account, e.rank);
  EXPECT_EQ(got, (std::vector<std::pair<AccountId, std::int64_t>>{
                     {p3, 1}, {p5, 1}, {p1, 3}, {p2, 3}, {p4, 3}, {p6, 6}}));
  EXPECT_DOUBLE_EQ(entries[2].value, 0.5);
  EXPECT_EQ(entries[5].value, 0);

  entries = board(LeaderboardKind::WinRate, 100, 2);
  got.clear();
  for (const auto& e : entries) got.emplace_back(e.account, e.rank);
  EXPECT_EQ(got,
            (std::vector<std::pair<AccountId, std::int64_t>>{{p3, 1}, {p1, 2}, {p2, 2}, {p4, 2}}));
  EXPECT_TRUE(board(LeaderboardKind::WinRate, 100, 3).empty());
  EXPECT_EQ(board(LeaderboardKind::WinRate, 100, 0).size(), 6u);  // at least one match anyway

  EXPECT_FALSE(must(store_->rank_of(p5, LeaderboardKind::WinRate, 2), "p5 min 2").has_value());
  EXPECT_EQ(must(store_->rank_of(p5, LeaderboardKind::WinRate, 1), "p5 min 1")->rank, 1);
  EXPECT_EQ(must(store_->rank_of(p4, LeaderboardKind::WinRate, 2), "p4 min 2")->rank, 2);
  EXPECT_EQ(must(store_->rank_of(p6, LeaderboardKind::WinRate, 1), "p6 min 1")->rank, 6);
  EXPECT_DOUBLE_EQ(must(store_->rank_of(p1, LeaderboardKind::WinRate, 2), "p1")->value, 0.5);
}

TEST_F(LeaderboardTest, RankOfAgreesWithTheBoard) {
  std::vector<AccountId> ids;
  for (int i = 0; i < 30; ++i) ids.push_back(add("player" + std::to_string(i)));
  std::uint32_t seed = 12345;
  const auto next = [&seed](std::uint32_t n) {
    seed = seed * 1664525u + 1013904223u;
    return (seed >> 8) % n;
  };
  for (int m = 0; m < 60; ++m) {
    std::vector<AccountId> shuffled = ids;
    for (std::size_t i = shuffled.size(); i > 1; --i) std::swap(shuffled[i - 1], shuffled[next(i)]);
    std::vector<PlayerResult> players;
    const std::size_t n = 2 + next(5);
    for (std::size_t i = 0; i < n; ++i)
      players.push_back(result(shuffled[i], static_cast<std::int32_t>(next(4)),
                               static_cast<std::int32_t>(next(6))));
    must(store_->record_match(match_of(players)), "random match");
  }
  for (LeaderboardKind kind :
       {LeaderboardKind::Rating, LeaderboardKind::Kills, LeaderboardKind::WinRate}) {
    for (int min_matches : {1, 4}) {
      const auto entries = board(kind, 1000, min_matches);
      for (std::size_t i = 0; i < entries.size(); ++i) {
        const LeaderboardEntry& e = entries[i];
        SCOPED_TRACE("kind " + std::to_string(static_cast<int>(kind)) + " min " +
                     std::to_string(min_matches) + " entry " + std::to_string(i));
        if (i > 0) {
          EXPECT_GE(entries[i - 1].value, e.value);
          if (entries[i - 1].value == e.value) {
            EXPECT_LT(entries[i - 1].account, e.account);
          }
        }
        EXPECT_GE(e.matches, kind == LeaderboardKind::WinRate ? min_matches : 1);
        const auto ranked = must(store_->rank_of(e.account, kind, min_matches), "rank_of");
        ASSERT_TRUE(ranked.has_value());
        EXPECT_EQ(ranked->rank, e.rank);
        EXPECT_EQ(ranked->value, e.value);
        EXPECT_EQ(ranked->matches, e.matches);
        EXPECT_EQ(ranked->username, e.username);
      }
    }
  }
}

/// The query plan of `sql`, one detail line per row.
std::vector<std::string> query_plan(sqlite3* db, const std::string& sql) {
  sqlite::Statement explain;
  EXPECT_EQ(explain.prepare(db, "EXPLAIN QUERY PLAN " + sql), SQLITE_OK) << sqlite3_errmsg(db);
  sqlite::Query q(explain);
  std::vector<std::string> lines;
  while (q.step() == SQLITE_ROW) lines.push_back(q.text(3));
  return lines;
}

TEST_F(SqliteStoreTest, LeaderboardQueriesWalkTheirIndexes) {
  sqlite::Connection raw;
  ASSERT_EQ(sqlite::open(path_, SQLITE_OPEN_READONLY, raw), SQLITE_OK);
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

}  // namespace
}  // namespace ricochet::db::test
