// Several server processes write match results to one PostgreSQL database at once: no update is
// lost. Each writer is a forked process with its own connection recording matches between the
// same few players (Matches::record_match: read the ratings, compute, write, in one
// transaction). Afterwards every match is replayed in commit order (match ids are given out
// under the write lock, so their order is the commit order) with the Elo of rating.h, and
// every stored rating_before, rating_after and final rating must equal the hand computation.
// A lost update (two writers reading the same rating) would break the chain.

#include <sys/wait.h>
#include <unistd.h>

#include <map>

#include "ricochet/db/matches.h"
#include "ricochet/db/rating.h"
#include "store_fixture.h"

namespace ricochet::db::test::concurrent_writers_test {
namespace {

constexpr int kWriters = 4;
constexpr int kMatchesPerWriter = 25;
constexpr int kPlayers = 6;

/// Writer `w`'s match `m`: three of the players, scores that differ per match.
MatchRecord match_for(const std::vector<AccountId>& players, int w, int m) {
  std::vector<PlayerResult> results;
  for (int k = 0; k < 3; ++k) {
    const auto i = static_cast<std::size_t>((w + m + k * 2) % kPlayers);
    results.push_back(result(players[i], (w * 7 + m * 3 + k * 5) % 11));
  }
  return match_of(results);
}

/// The body of a writer process: 0 when every match was recorded.
int write_matches(const std::string& url, const std::vector<AccountId>& players, int w) {
  auto store = open_store({.url_or_path = url, .busy_timeout_ms = 30'000});
  if (!store.ok()) return 2;
  Matches matches(*store.value());
  for (int m = 0; m < kMatchesPerWriter; ++m)
    if (!matches.record_match(match_for(players, w, m)).ok()) return 3;
  return 0;
}

TEST(ConcurrentWriters, ProcessesWritingResultsAtOnceLoseNoRatingUpdate) {
  const TestDatabase db(Backend::Postgres);
  std::vector<AccountId> players;
  {
    auto store = db.open();
    for (int i = 0; i < kPlayers; ++i) {
      const std::string name = "player" + std::to_string(i);
      players.push_back(must(store->insert_account(name, name, "h", 0), "insert_account"));
    }
  }
  std::vector<pid_t> writers;
  for (int w = 0; w < kWriters; ++w) {
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) _exit(write_matches(db.url_or_path(), players, w));  // no gtest in the child
    writers.push_back(pid);
  }
  for (pid_t pid : writers) {
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "writer status " << status;
  }

  // Replay in commit order.
  postgres::Connection raw = db.connect();
  postgres::Result r = postgres::exec(
      raw.get(),
      "SELECT match_id, account_id, score, rating_before, rating_after FROM match_players"
      " ORDER BY match_id, account_id");
  ASSERT_TRUE(r.ok()) << PQresultErrorMessage(r.get());
  ASSERT_EQ(r.rows(), kWriters * kMatchesPerWriter * 3);
  std::map<AccountId, double> rating;
  for (AccountId p : players) rating[p] = kInitialRating;
  int checked = 0;
  for (int row = 0; row < r.rows(); row += 3) {
    std::vector<RatedScore> scores;
    for (int k = 0; k < 3; ++k) {
      ASSERT_EQ(r.integer(row + k, 0), r.integer(row, 0)) << "a match without 3 players";
      const AccountId id = r.integer(row + k, 1);
      EXPECT_DOUBLE_EQ(r.real(row + k, 3), rating[id]) << "match " << r.integer(row, 0);
      scores.push_back({rating[id], static_cast<double>(r.integer(row + k, 2)), 0});
    }
    const std::vector<double> after = updated_ratings(scores);
    for (int k = 0; k < 3; ++k) {
      const AccountId id = r.integer(row + k, 1);
      rating[id] = after[static_cast<std::size_t>(k)];
      EXPECT_DOUBLE_EQ(r.real(row + k, 4), rating[id]) << "match " << r.integer(row, 0);
    }
    ++checked;
  }
  ASSERT_TRUE(r.column_error().empty()) << r.column_error();
  EXPECT_EQ(checked, kWriters * kMatchesPerWriter);
  auto store = db.open();
  std::int64_t participations = 0;
  for (AccountId p : players) {
    const PlayerStats stats = must(store->player_stats(p), "player_stats");
    EXPECT_DOUBLE_EQ(stats.rating, rating[p]) << stats.username;
    participations += stats.matches;
  }
  EXPECT_EQ(participations, kWriters * kMatchesPerWriter * 3);
}

}  // namespace
}  // namespace ricochet::db::test::concurrent_writers_test
