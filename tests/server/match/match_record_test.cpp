// Who counts in a match's record, and for how long: from the scoreboard, on simulation ticks,
// with fake time and no sockets.

#include "ricochet/server/match_record.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <span>
#include <string>
#include <variant>

#include "ricochet/proto/input_wire.h"
#include "ricochet/server/map.h"
#include "ricochet/server/match.h"

namespace ricochet::server::match_record_test {
namespace {

using proto::kMicrosPerSecond;
using proto::TimeUs;

constexpr TimeUs kStart = 1'000'000;

PlayerScore score(std::uint64_t account, std::uint32_t ticks, int kills, int deaths) {
  PlayerScore s;
  s.account = account;
  s.ticks_played = ticks;
  s.kills = kills;
  s.deaths = deaths;
  return s;
}

TEST(MatchRecord, ThoseWhoTookPartWhileRunningCountForTheirRunningTicks) {
  const std::vector<PlayerScore> board{
      score(1, 0, 0, 0),    // only waited or warmed up
      score(2, 120, 0, 0),  // two seconds at 60 Hz
      score(3, 0, 1, 0),    // away, but its rocket killed
      score(4, 0, 0, 1),    // away, and died
      score(5, 30, 2, 1),
  };
  const std::vector<CountedPlayer> counted = counted_players(board, 60);
  ASSERT_EQ(counted.size(), 4u);
  EXPECT_EQ(counted[0].score.account, 2u);
  EXPECT_EQ(counted[0].seconds_played, 2.0);
  EXPECT_EQ(counted[1].score.account, 3u);
  EXPECT_EQ(counted[1].seconds_played, 0.0);
  EXPECT_EQ(counted[2].score.account, 4u);
  EXPECT_EQ(counted[3].score.account, 5u);
  EXPECT_EQ(counted[3].seconds_played, 0.5);
  EXPECT_FALSE(counts_in_record(board[0]));
  EXPECT_EQ(counted_players(board, 30)[0].seconds_played, 4.0);  // the rate the ticks ran at
}

class MatchRecordFixture : public ::testing::Test {
 protected:
  static Match make(int min_players) {
    const std::string path = std::string(RICOCHET_SOURCE_DIR "/server/maps/arena.toml");
    MapResult map = load_map_file(path);
    EXPECT_TRUE(std::holds_alternative<Map>(map));
    MatchConfig config;
    config.rules.min_players = min_players;
    config.rules.warmup_s = 0;
    auto created = Match::create(config, std::get<Map>(map), kStart);
    if (auto* error = std::get_if<std::string>(&created)) ADD_FAILURE() << *error;
    return std::get<Match>(std::move(created));
  }

  /// Runs `match` for `ticks` whole ticks of fake time, emptying its outbox.
  void run(Match& match, int ticks) {
    for (int k = 0; k < ticks; ++k) {
      now_ += kMicrosPerSecond / match.config().tick.rate_hz + 1;
      match.tick(now_);
      Outgoing out;
      while (match.poll_outbox(out)) {
      }
    }
  }

  const CountedPlayer* find(const std::vector<CountedPlayer>& counted, std::uint64_t account) {
    for (const CountedPlayer& player : counted) {
      if (player.score.account == account) return &player;
    }
    return nullptr;
  }

  TimeUs now_ = kStart;
};

TEST_F(MatchRecordFixture, APlayerWhoOnlyWaitedDoesNotCount) {
  Match match = make(2);  // one player never starts the match
  ASSERT_TRUE(std::holds_alternative<Joined>(match.connect(1, "ann")));
  run(match, 120);
  EXPECT_EQ(match.phase(), MatchPhase::Waiting);
  EXPECT_TRUE(counted_players(match.scoreboard(), 60).empty());
}

TEST_F(MatchRecordFixture, TimeCountsWhileConnectedAndRunningAndSurvivesLeaving) {
  Match match = make(1);
  ASSERT_TRUE(std::holds_alternative<Joined>(match.connect(1, "ann")));
  ASSERT_TRUE(std::holds_alternative<Joined>(match.connect(2, "bob")));
  run(match, 60);
  ASSERT_EQ(match.phase(), MatchPhase::Running);
  const auto first = counted_players(match.scoreboard(), 60);
  const CountedPlayer* ann = find(first, 1);
  ASSERT_NE(ann, nullptr);
  const std::uint32_t ann_ticks = ann->score.ticks_played;
  EXPECT_GE(ann_ticks, 58u);
  EXPECT_LE(ann_ticks, 60u);
  EXPECT_EQ(ann->seconds_played, ann_ticks / 60.0);

  // Ann is away for a second: her time stops. Bob leaves for good: he still counts.
  match.disconnect(1, now_);
  ASSERT_TRUE(match.leave(2));
  run(match, 60);
  const auto second = counted_players(match.scoreboard(), 60);
  ASSERT_NE(find(second, 1), nullptr);
  EXPECT_EQ(find(second, 1)->score.ticks_played, ann_ticks);
  ASSERT_NE(find(second, 2), nullptr);
  EXPECT_EQ(find(second, 2)->seconds_played, find(first, 2)->seconds_played);

  // Back: her time goes on from where it stopped.
  ASSERT_TRUE(std::holds_alternative<Joined>(match.connect(1, "ann")));
  run(match, 30);
  const auto third = counted_players(match.scoreboard(), 60);
  EXPECT_EQ(find(third, 1)->score.ticks_played, ann_ticks + 30);
}

TEST_F(MatchRecordFixture, APlayerWhoLeavesKeepsItsScoreOnlyWhenItCounts) {
  // Ann fires in the step that starts the match and leaves before its next one: a shot, but no
  // running tick connected, no kill, no death. The scoreboard forgets her, as the record does.
  Match match = make(2);
  const auto ann = std::get<Joined>(match.connect(1, "ann"));
  ASSERT_TRUE(std::holds_alternative<Joined>(match.connect(2, "bob")));
  RecordedInput fire;
  fire.entity_id = ann.entity_id;
  fire.input.sequence = 1;
  fire.input.buttons = proto::kButtonFire;
  match.step_recorded(std::span(&fire, 1));
  ASSERT_EQ(match.phase(), MatchPhase::Running);
  const std::vector<PlayerScore> before = match.scoreboard();
  ASSERT_EQ(before.size(), 2u);
  EXPECT_EQ(before[0].account, 1u);
  EXPECT_EQ(before[0].shots, 1);
  EXPECT_FALSE(counts_in_record(before[0]));

  ASSERT_TRUE(match.leave(1));
  const std::vector<PlayerScore> after = match.scoreboard();
  ASSERT_EQ(after.size(), 1u);
  EXPECT_EQ(after[0].account, 2u);
}

}  // namespace
}  // namespace ricochet::server::match_record_test
