// The Store contract on both backends (a real SQLite file, a real PostgreSQL database): accounts,
// sessions, transactions, matches with their stats as the match rules hand them over (the rules
// are tested in matches_test.cpp), persistence across reopening, lock timeouts. A second, raw
// connection looks at what was actually written.

#include "ricochet/db/store.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "ricochet/db/rating.h"
#include "store_fixture.h"

namespace ricochet::db::test::store_test {
namespace {

std::string token_hash(char seed) {
  std::string hash(32, '\0');
  for (std::size_t i = 0; i < hash.size(); ++i) hash[i] = static_cast<char>(seed * 31 + i);
  hash[5] = '\0';  // binary data: an embedded zero must survive
  return hash;
}

using StoreContractTest = StoreTest;

// --- accounts ---

TEST_P(StoreContractTest, InsertsAndFindsAccounts) {
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

TEST_P(StoreContractTest, DuplicateUsernameKeyIsRefused) {
  add("Alice");
  const auto again = store_->insert_account("ALICE", "alice", "h", 2000);
  ASSERT_TRUE(fails_with(again, DbErrorCode::DuplicateUsername));
  EXPECT_NE(again.error().message.find("ALICE"), std::string::npos) << again.error().message;
  EXPECT_EQ(rows("accounts"), 1);
}

TEST_P(StoreContractTest, UpdatesAccountFields) {
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

TEST_P(StoreContractTest, SessionLifecycle) {
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

TEST_P(StoreContractTest, SessionRejectsBadHashAndUnknownAccount) {
  const AccountId id = add("alice");
  EXPECT_TRUE(fails_with(store_->insert_session(std::string(31, 'x'), id, 1, 2),
                         DbErrorCode::UnknownSession));
  EXPECT_TRUE(
      fails_with(store_->insert_session(token_hash(1), id + 1, 1, 2), DbErrorCode::UnknownAccount));
  EXPECT_FALSE(must(store_->find_session("short"), "find short").has_value());
  RICOCHET_DB_EXPECT_OK(store_->delete_session("short"));
  EXPECT_EQ(rows("sessions"), 0);
}

TEST_P(StoreContractTest, DeletesSessionsOfOneAccount) {
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

TEST_P(StoreContractTest, DeletesExpiredSessions) {
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

// --- transactions ---

TEST_P(StoreContractTest, ATransactionCommitsAllOrNothing) {
  const AccountId a = add("alice");
  const AccountId b = add("bob");
  const DbStatus failed = store_->transaction([&]() -> DbStatus {
    RICOCHET_DB_EXPECT_OK(store_->set_banned(a, true));
    // A transaction inside joins this one, and is undone with it.
    RICOCHET_DB_EXPECT_OK(store_->transaction([&] { return store_->set_banned(b, true); }));
    return store_->set_banned(a + b, true);  // no such account
  });
  EXPECT_TRUE(fails_with(failed, DbErrorCode::UnknownAccount));
  EXPECT_EQ(raw_integer("SELECT COUNT(*) FROM accounts WHERE banned = 1"), 0);
  RICOCHET_DB_ASSERT_OK(store_->transaction([&]() -> DbStatus {
    if (DbStatus s = store_->set_banned(a, true); !s.ok()) return s;
    return store_->set_banned(b, true);
  }));
  EXPECT_EQ(raw_integer("SELECT COUNT(*) FROM accounts WHERE banned = 1"), 2);
  // atomically() hands back the work's own result, or its error.
  EXPECT_EQ(must(atomically(*store_, [&] { return store_->account(b); }), "atomically").id, b);
  EXPECT_TRUE(fails_with(atomically(*store_, [&] { return store_->account(a + b); }),
                         DbErrorCode::UnknownAccount));
}

// --- matches and stats, as the match rules hand them over ---

TEST_P(StoreContractTest, InsertMatchWritesTheMatchItsPlayersAndTheirTotals) {
  const AccountId winner = add("alice");
  const AccountId loser = add("bob");
  EXPECT_FALSE(must(store_->rating_of(winner), "rating before any match").has_value());
  EXPECT_TRUE(fails_with(store_->rating_of(loser + 1), DbErrorCode::UnknownAccount));
  const MatchRecord match = match_of({result(winner, 10, 3), result(loser, 5, 1)});
  const MatchId id = must(
      store_->insert_match(match, {{1500, 1531.25, true}, {1500, 1470.5, false}}), "insert_match");
  EXPECT_EQ(must(store_->match_count(), "count"), 1);
  EXPECT_EQ(raw_integer("SELECT COUNT(*) FROM matches WHERE id = " + std::to_string(id) +
                        " AND map = 'foundry' AND mode = 'ffa' AND started_ms = 1000000"
                        " AND ended_ms = 1300000 AND tick_rate = 60"),
            1);
  EXPECT_EQ(raw_integer(
                "SELECT COUNT(*) FROM match_players WHERE account_id = " + std::to_string(winner) +
                " AND rating_before = 1500 AND rating_after = 1531.25 AND kills = 3"),
            1);
  EXPECT_EQ(
      raw_integer("SELECT COUNT(*) FROM match_players WHERE account_id = " + std::to_string(loser) +
                  " AND rating_before = 1500 AND rating_after = 1470.5"),
      1);

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
  EXPECT_DOUBLE_EQ(w.rating, 1531.25);
  EXPECT_EQ(must(store_->player_stats(loser), "loser stats").wins, 0);
  EXPECT_EQ(must(store_->rating_of(loser), "rating after"), 1470.5);

  // A second match adds to the totals and replaces the rating.
  must(store_->insert_match(match_of({result(winner, 1, 4), result(loser, 9, 6)}),
                            {{1531.25, 1520, false}, {1470.5, 1481.75, true}}),
       "second match");
  const PlayerStats w2 = must(store_->player_stats(winner), "winner after two");
  EXPECT_EQ(w2.matches, 2);
  EXPECT_EQ(w2.wins, 1);
  EXPECT_EQ(w2.kills, 7);
  EXPECT_EQ(w2.score, 11);
  EXPECT_DOUBLE_EQ(w2.damage_dealt, 241);
  EXPECT_DOUBLE_EQ(w2.seconds_played, 600);
  EXPECT_DOUBLE_EQ(w2.rating, 1520);
  EXPECT_EQ(must(store_->player_stats(loser), "loser after two").wins, 1);

  EXPECT_TRUE(
      fails_with(store_->insert_match(match, {{1500, 1500, true}}), DbErrorCode::InvalidMatch));
  EXPECT_EQ(must(store_->match_count(), "count"), 2);
}

TEST_P(StoreContractTest, PlayerStatsOfAnAccountThatNeverPlayed) {
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

TEST_P(StoreContractTest, AnInsertMatchFailingHalfWayWritesNothing) {
  const AccountId a = add("a"), b = add("b"), c = add("c");
  const std::vector<PlayerOutcome> two = {{1500, 1516, true}, {1500, 1484, false}};
  must(store_->insert_match(match_of({result(a, 5), result(b, 3)}), two), "first match");
  // The third player's stats fail, after the match and its players are written.
  db_.inject_failure("BEFORE INSERT ON player_stats", "NEW.account_id = " + std::to_string(c));
  const auto failed = store_->insert_match(match_of({result(a, 1), result(b, 2), result(c, 3)}),
                                           {{1516, 1, false}, {1484, 2, false}, {1500, 3, true}});
  ASSERT_TRUE(fails_with(failed, DbErrorCode::Storage));
  EXPECT_NE(failed.error().message.find("injected failure"), std::string::npos)
      << failed.error().message;
  EXPECT_NE(failed.error().message.find(db_.where()), std::string::npos) << failed.error().message;
  EXPECT_EQ(rows("matches"), 1);
  EXPECT_EQ(rows("match_players"), 2);
  EXPECT_EQ(raw_integer("SELECT SUM(matches) FROM player_stats"), 2);
  EXPECT_DOUBLE_EQ(must(store_->player_stats(a), "a").rating, 1516);
}

TEST_P(StoreContractTest, WriteLockHeldElsewhereIsBusy) {
  store_ = db_.open(50);
  const AccountId a = add("a");
  TestDatabase::WriteLock other(db_);
  // SQLite's lock covers every write; PostgreSQL's only transactions (Store::transaction), which
  // is what the rules above the store write through when reads and writes must go together.
  if (!db_.postgres()) {
    EXPECT_TRUE(fails_with(store_->insert_account("b", "b", "h", 1), DbErrorCode::Busy));
  }
  const auto blocked = store_->insert_match(match_of({result(a, 1)}), {{1500, 1500, true}});
  ASSERT_TRUE(fails_with(blocked, DbErrorCode::Busy));
  EXPECT_NE(blocked.error().message.find("retry later"), std::string::npos)
      << blocked.error().message;
  EXPECT_TRUE(must(store_->account(a), "reads go on").id == a);
  other.release();
  must(store_->insert_match(match_of({result(a, 1)}), {{1500, 1500, true}}),
       "after the lock is released");
}

TEST_P(StoreContractTest, DataSurvivesCloseAndReopen) {
  const AccountId a = add("alice"), b = add("bob");
  RICOCHET_DB_ASSERT_OK(store_->insert_session(token_hash(7), a, 10, 20));
  must(store_->insert_match(match_of({result(a, 10), result(b, 5)}),
                            {{1500, 1516, true}, {1500, 1484, false}}),
       "insert_match");
  reopen();
  EXPECT_EQ(must(store_->account(b), "bob").username, "bob");
  EXPECT_TRUE(must(store_->find_session(token_hash(7)), "session").has_value());
  EXPECT_EQ(must(store_->match_count(), "count"), 1);
  EXPECT_DOUBLE_EQ(must(store_->player_stats(a), "alice").rating, 1516);
  EXPECT_TRUE(
      fails_with(store_->insert_account("Alice", "alice", "h", 0), DbErrorCode::DuplicateUsername));
}

INSTANTIATE_TEST_SUITE_P(Backends, StoreContractTest, kBackends, backend_name);

}  // namespace
}  // namespace ricochet::db::test::store_test
