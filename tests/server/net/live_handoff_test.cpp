// The live view's hand-off between threads, as the server runs it (server_live.cpp): the match
// publishes frames on its strand while viewers take seats, encode frames and leave on others
// (the admin port's). It lives in server_tests, beside the network layer whose threads it
// stands for, because that is the binary the ThreadSanitizer pass builds (tools/test.sh), not
// match_tests (the single-threaded match library).

#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

#include "frame_json.h"
#include "ricochet/server/match.h"

namespace ricochet::server::live_handoff_test {
namespace {

TEST(FrameStream, ViewersOnTheirOwnThreadsWhileTheMatchTicks) {
  Map map;
  map.name = "flat";
  map.bounds_min_m = physics::Vec3(-20, -5, -20);
  map.bounds_max_m = physics::Vec3(20, 15, 20);
  map.floor_y_m = 0.0f;
  map.spawns.push_back(MapSpawn{physics::Vec3(0, 0.4f, 5), 0.0f, Team::None});
  MatchConfig config;
  config.record = false;
  auto created = Match::create(config, map, 0);
  ASSERT_TRUE(std::holds_alternative<Match>(created));
  Match match = std::get<Match>(std::move(created));
  LiveFeedConfig feed_config;
  feed_config.rate_hz = 60;
  feed_config.max_viewers = 2;
  auto feed = std::make_shared<LiveFeed>(feed_config);
  match.set_live_feed(feed);
  match.connect(1, "ann");
  std::atomic<bool> done{false};
  std::atomic<int> frames{0};
  // Two viewers come and go and encode what they get, on their threads, until the match is done.
  std::vector<std::thread> viewers;
  for (int v = 0; v < 2; ++v) {
    viewers.emplace_back([&] {
      while (!done.load()) {
        std::optional<LiveFeed::Viewer> seat = feed->watch();
        if (!seat) continue;
        web::FrameStream stream(std::move(*seat));
        for (int k = 0; k < 50 && !done.load(); ++k) {
          if (const std::optional<std::string> json = stream.next()) {
            EXPECT_EQ(json->rfind("{\"match\":1,", 0), 0u);
            frames.fetch_add(1);
          }
        }
      }
    });
  }
  proto::TimeUs now = 0;
  // 300 ticks at least, then on until a viewer has shown a frame (its thread may start late on a
  // busy machine), within a bound.
  for (int tick = 0; tick < 1'000'000 && (tick < 300 || frames.load() == 0); ++tick) {
    if (tick >= 300) std::this_thread::yield();
    match.tick(now += proto::kMicrosPerSecond / 60);
    Outgoing out;
    while (match.poll_outbox(out)) {
    }
  }
  done.store(true);
  for (std::thread& viewer : viewers) viewer.join();
  EXPECT_GT(frames.load(), 0);
  EXPECT_EQ(feed->viewers(), 0);
}

}  // namespace
}  // namespace ricochet::server::live_handoff_test
