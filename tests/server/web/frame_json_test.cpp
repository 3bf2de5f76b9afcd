// A live frame's JSON, a viewer's stream of frames, the bounded seats of a feed, and the match
// id a URL names (server/src/web/frame_json.h, match_id.h).

#include "frame_json.h"

#include <gtest/gtest.h>

#include "match_id.h"
#include "ricochet/server/match.h"

namespace ricochet::server::web::frame_json_test {
namespace {

LiveFrame sample_frame() {
  LiveFrame frame;
  frame.match_id = 7;
  frame.tick = 1234;
  frame.server_time_us = 20'566'666;
  frame.tick_rate_hz = 60;
  frame.phase = MatchPhase::Running;
  frame.time_left_s = 95.5;
  frame.mode = GameMode::TeamDeathmatch;
  frame.team_scores = {0, 3, 2};
  LivePlayer ann;
  ann.entity_id = 1;
  ann.name = "ann \"the\" one";
  ann.team = Team::Red;
  ann.position_m = {1.25f, 0.45f, -3.0f};
  ann.velocity_mps = {6.0f, 0.0f, -0.126f};
  ann.yaw_rad = -1.5707963f;
  ann.health = 75;
  ann.armor = 10;
  ann.alive = true;
  ann.connected = true;
  ann.weapon = WeaponKind::RocketLauncher;
  ann.kills = 3;
  ann.deaths = 1;
  ann.score = 2;
  frame.players.push_back(ann);
  LivePlayer ben;
  ben.entity_id = 2;
  ben.name = "ben";
  ben.team = Team::Blue;
  ben.position_m = {-4.0f, 0.45f, 2.5f};
  frame.players.push_back(ben);
  frame.projectiles.push_back(
      LiveProjectile{9, LiveProjectileKind::Grenade, 1, {0.5f, 1.0f, -2.0f}, {3.0f, 2.5f, 0.0f}});
  frame.kills.push_back(LiveKill{1230, 1, 2, WeaponKind::RocketLauncher});
  frame.kills.push_back(LiveKill{1231, 0, 1, std::nullopt});
  return frame;
}

TEST(FrameJson, EveryFieldWithItsUnits) {
  EXPECT_EQ(
      frame_json(sample_frame()),
      "{\"match\":7,\"tick\":1234,\"server_time_us\":20566666,\"tick_rate_hz\":60,"
      "\"phase\":\"running\",\"time_left_s\":95.5,\"mode\":\"tdm\","
      "\"team_scores\":{\"red\":3,\"blue\":2},\"players\":["
      "{\"id\":1,\"name\":\"ann \\\"the\\\" one\",\"team\":\"red\",\"position\":[1.25,0.45,-3],"
      "\"velocity\":[6,0,-0.13],\"yaw\":-1.5708,\"health\":75,\"armor\":10,\"alive\":true,"
      "\"connected\":true,\"weapon\":\"rocket_launcher\",\"kills\":3,\"deaths\":1,\"score\":2},"
      "{\"id\":2,\"name\":\"ben\",\"team\":\"blue\",\"position\":[-4,0.45,2.5],"
      "\"velocity\":[0,0,0],\"yaw\":0,\"health\":0,\"armor\":0,\"alive\":false,"
      "\"connected\":false,\"weapon\":\"rifle\",\"kills\":0,\"deaths\":0,\"score\":0}],"
      "\"projectiles\":[{\"id\":9,\"kind\":\"grenade\",\"owner\":1,\"position\":[0.5,1,-2],"
      "\"velocity\":[3,2.5,0]}],"
      "\"kills\":[{\"tick\":1230,\"killer\":1,\"victim\":2,\"weapon\":\"rocket_launcher\"},"
      "{\"tick\":1231,\"killer\":0,\"victim\":1,\"weapon\":null}],\"kills_dropped\":0}");
}

TEST(FrameJson, NonFiniteNumbersAreNull) {
  LiveFrame frame;
  frame.time_left_s = std::nullopt;
  LivePlayer player;
  player.position_m = {std::numeric_limits<float>::quiet_NaN(),
                       std::numeric_limits<float>::infinity(), -0.0f};
  frame.players.push_back(player);
  const std::string json = frame_json(frame);
  EXPECT_NE(json.find("\"time_left_s\":null"), std::string::npos);
  EXPECT_NE(json.find("\"position\":[null,null,0]"), std::string::npos) << json;
}

TEST(FrameStream, HandsOutEachFrameOnceAndOnlyWhileWatched) {
  auto feed = std::make_shared<LiveFeed>(LiveFeedConfig{});
  auto frame = std::make_shared<LiveFrame>(sample_frame());
  feed->publish(frame);  // nobody watches: dropped
  std::optional<LiveFeed::Viewer> viewer = feed->watch();
  ASSERT_TRUE(viewer);
  FrameStream stream(std::move(*viewer));
  EXPECT_FALSE(stream.next());
  feed->publish(frame);
  const std::optional<std::string> first = stream.next();
  ASSERT_TRUE(first);
  EXPECT_EQ(*first, frame_json(*frame));
  EXPECT_FALSE(stream.next());  // the same frame again
  auto later = std::make_shared<LiveFrame>(sample_frame());
  later->tick = 1237;
  feed->publish(later);
  const std::optional<std::string> second = stream.next();
  ASSERT_TRUE(second);
  EXPECT_NE(second->find("\"tick\":1237"), std::string::npos);
}

TEST(LiveFeed, SeatsAreBoundedAndTheLastToLeaveForgetsTheFrame) {
  LiveFeedConfig config;
  config.max_viewers = 2;
  ASSERT_EQ(config.validate(), "");
  auto feed = std::make_shared<LiveFeed>(config);
  EXPECT_FALSE(feed->watched());
  std::optional<LiveFeed::Viewer> a = feed->watch();
  std::optional<LiveFeed::Viewer> b = feed->watch();
  ASSERT_TRUE(a && b);
  EXPECT_FALSE(feed->watch());  // full
  EXPECT_EQ(feed->viewers(), 2);
  feed->publish(std::make_shared<LiveFrame>(sample_frame()));
  ASSERT_TRUE(b->latest());
  a.reset();
  EXPECT_EQ(feed->viewers(), 1);
  EXPECT_TRUE(feed->watch());  // a seat again (given back at once)
  EXPECT_TRUE(b->latest());
  b.reset();
  EXPECT_FALSE(feed->watched());
  EXPECT_EQ(feed->latest(), nullptr);
}

TEST(LiveFeed, ConfigIsValidated) {
  EXPECT_EQ(LiveFeedConfig{}.validate(), "");
  EXPECT_EQ((LiveFeedConfig{0, 8}).validate(), "rate_hz must be 1..60, got 0");
  EXPECT_EQ((LiveFeedConfig{61, 8}).validate(), "rate_hz must be 1..60, got 61");
  EXPECT_EQ((LiveFeedConfig{20, 0}).validate(), "max_viewers must be 1..64, got 0");
  EXPECT_EQ((LiveFeedConfig{20, 65}).validate(), "max_viewers must be 1..64, got 65");
  EXPECT_EQ(LiveFeed(LiveFeedConfig{}).interval_us(), 50'000);
}

TEST(MatchId, AcceptsOnlyPlainDecimalIds) {
  const auto id = [](std::string_view text) {
    const auto parsed = parse_match_id(text);
    return std::holds_alternative<std::uint32_t>(parsed) ? std::get<std::uint32_t>(parsed) : 0u;
  };
  EXPECT_EQ(id("1"), 1u);
  EXPECT_EQ(id("42"), 42u);
  EXPECT_EQ(id("4294967295"), 4294967295u);
  for (const std::string_view bad : std::initializer_list<std::string_view>{
           "", "0", "007", "-1", "+1", " 1", "1 ", "1a", "0x10", "4294967296", "99999999999",
           "12345678901234567890", "1/2", "%31", std::string_view("1\0", 2)}) {
    const auto parsed = parse_match_id(bad);
    ASSERT_TRUE(std::holds_alternative<std::string>(parsed)) << "accepted " << bad;
    EXPECT_FALSE(std::get<std::string>(parsed).empty());
  }
  EXPECT_EQ(std::get<std::string>(parse_match_id("99999999999")),
            "match id must be 1..10 digits, got 11 bytes");
}

}  // namespace
}  // namespace ricochet::server::web::frame_json_test
