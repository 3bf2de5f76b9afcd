// The Recordings routes as requests and replies (replay_routes.h), over a recordings directory
// of scripted recordings, the replay pool and its workers: bad ids are 400, unknown recordings,
// paths and actions 404, tick queries checked to the digit, frames before the replay is done
// 409, each refusal counted where /metrics reads it; more replays than max_replays are 503 with
// the reason; a running replay, held mid-run by the pool's step hook, cancels, frees its worker
// for the next; a replayed kill is in the frames the page reads, as the match told its players.
// The tests wait for the workers on their state (bounded), never on time.

#include "replay_routes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <fstream>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "scripted_recording.h"
#include "temp_dir.h"

namespace ricochet::server::replay_routes_test {
namespace {

constexpr const char* kId = "match-3-1764966123456";
constexpr const char* kOtherId = "match-4-1764966123457";
constexpr const char* kThirdId = "match-5-1764966123458";
constexpr const char* kMapView = "{\"map\":\"arena\"}";

/// The scripted recording (made once) and the kills its match told its players.
struct Recorded {
  std::vector<std::uint8_t> bytes;
  std::vector<wire::Kill> kills;
};
const Recorded& recorded() {
  static const Recorded once = [] {
    Recorded r;
    r.bytes = web_test::scripted_recording(600, &r.kills);
    return r;
  }();
  return once;
}

/// Holds the replay of one recording after one step until released: a worker kept busy
/// mid-replay. Waits are bounded (30 s).
class Hold {
 public:
  Hold(std::string id, std::uint32_t tick) : id_(std::move(id)), tick_(tick) {}
  ReplayJobs::StepHook hook() {
    return [this](const std::string& id, std::uint32_t tick) {
      if (id != id_ || tick != tick_) return;
      std::unique_lock lock(mutex_);
      held_ = true;
      changed_.notify_all();
      changed_.wait_for(lock, std::chrono::seconds(30), [&] { return released_; });
    };
  }
  bool wait_held() {
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, std::chrono::seconds(30), [&] { return held_; });
  }
  void release() {
    const std::lock_guard lock(mutex_);
    released_ = true;
    changed_.notify_all();
  }

 private:
  const std::string id_;
  const std::uint32_t tick_;
  std::mutex mutex_;
  std::condition_variable changed_;
  bool held_ = false;
  bool released_ = false;
};

class ReplayRoutesTest : public ::testing::Test {
 protected:
  ReplayRoutesTest() {
    for (const char* id : {kId, kOtherId, kThirdId}) {
      std::ofstream out(dir_.path() / (std::string(id) + ".rcr"), std::ios::binary);
      out.write(reinterpret_cast<const char*>(recorded().bytes.data()),
                static_cast<std::streamsize>(recorded().bytes.size()));
    }
  }
  void TearDown() override { hold_.release(); }

  RecordingsReply get(const std::string& rest, const std::string& query = {}) {
    const std::string path = "/api/recordings/" + rest;
    return routes_.answer({"GET", path, query});
  }
  RecordingsReply post(const std::string& rest) {
    const std::string path = "/api/recordings/" + rest;
    return routes_.answer({"POST", path, {}});
  }
  /// Until the job is no longer queued or running (bounded: its last status after 30 s).
  ReplayJobStatus wait_finished(const std::string& id) {
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    for (;;) {
      const auto status = jobs_.status(id);
      if (!status) return {};
      if ((status->state != ReplayJobState::Queued && status->state != ReplayJobState::Running) ||
          std::chrono::steady_clock::now() > give_up) {
        return *status;
      }
      std::this_thread::yield();
    }
  }

  ricochet::test::TempDir dir_{"ricochet-routes"};
  RecordingCatalog catalog_{dir_.path()};
  Hold hold_{kId, 10};
  ReplayJobs jobs_{{.workers = 1, .max_replays = 2, .memory_mb = 16},
                   recording_source(catalog_),
                   [] { return 0.0; },
                   hold_.hook()};
  ReplayRoutes::MapViews map_views_{{"arena", kMapView}};
  ReplayRoutes routes_{catalog_, jobs_, map_views_};
};

TEST_F(ReplayRoutesTest, BadIdsUnknownRecordingsAndActionsAreRefusedAndCounted) {
  // A bad id: 400, counted by the catalog (reason bad_id).
  for (const char* rest : {"", "nope", "match-3-x", "..", "match-3-1764966123456.rcr"}) {
    const RecordingsReply reply = get(rest);
    EXPECT_EQ(reply.status, 400u) << rest;
    EXPECT_TRUE(reply.body.starts_with("bad recording id: a recording id is match-")) << reply.body;
  }
  EXPECT_EQ(post("nope/replay").status, 400u);
  EXPECT_EQ(catalog_.bad_ids(), 6u);
  EXPECT_EQ(routes_.bad_requests(), 0u);

  // A good id with no file, an unknown path or action: 404, counted (reason bad_request).
  const RecordingsReply unknown = get("match-9-1764966123456");
  EXPECT_EQ(unknown.status, 404u);
  EXPECT_EQ(unknown.body, "no recording match-9-1764966123456\n");
  EXPECT_EQ(routes_.bad_requests(), 1u);
  EXPECT_EQ(post("match-9-1764966123456/replay").status, 404u);
  EXPECT_EQ(routes_.bad_requests(), 2u);
  EXPECT_EQ(get(std::string(kId) + "/nothing").body, "unknown recording path\n");
  EXPECT_EQ(get(std::string(kId) + "/frames/more", "from=1&to=2").status, 404u);
  EXPECT_EQ(routes_.bad_requests(), 4u);
  const RecordingsReply action = post(std::string(kId) + "/frames");
  EXPECT_EQ(action.status, 404u);
  EXPECT_EQ(action.body, "unknown recording action\n");
  EXPECT_EQ(routes_.bad_requests(), 5u);

  // The page's own timing, not counted: nothing to cancel, frames before the replay.
  EXPECT_EQ(post(std::string(kId) + "/cancel").status, 404u);
  const RecordingsReply early = get(std::string(kId) + "/frames", "from=1&to=2");
  EXPECT_EQ(early.status, 409u);
  EXPECT_EQ(early.body, "not replayed yet: POST .../replay and wait for done\n");
  EXPECT_EQ(routes_.bad_requests(), 5u);
  EXPECT_EQ(catalog_.bad_ids(), 6u);

  // What is there: the recording, never replayed; its map; the list.
  const RecordingsReply read = get(kId);
  EXPECT_EQ(read.status, 200u);
  EXPECT_EQ(read.content_type, "application/json");
  EXPECT_EQ(read.body, std::string("{\"id\":\"") + kId + "\",\"job\":null,\"summary\":null}");
  EXPECT_EQ(get(std::string(kId) + "/map").body, kMapView);
  const RecordingsReply list = routes_.list();
  EXPECT_EQ(list.status, 200u);
  EXPECT_NE(list.body.find(std::string("\"id\":\"") + kId + "\""), std::string::npos);
}

TEST_F(ReplayRoutesTest, TickQueriesAreCheckedBeforeAnyFrameIsRead) {
  hold_.release();
  ASSERT_EQ(post(std::string(kId) + "/replay").status, 200u);
  const ReplayJobStatus done = wait_finished(kId);
  ASSERT_EQ(done.state, ReplayJobState::Done) << done.error;
  const std::string last = std::to_string(done.ticks_total);

  struct Case {
    const char* query;
    unsigned status;
  };
  const std::string past_end = "from=1&to=" + std::to_string(done.ticks_total + 2);
  const Case cases[] = {
      {"", 400},                               // missing
      {"from=1", 400},                         // `to` missing
      {"from=&to=2", 400},                     // empty
      {"from=+1&to=2", 400},                   // a sign
      {"from=-1&to=2", 400},                   //
      {"from=1&to=2x", 400},                   // not a number to its end
      {"from=12345678901&to=2", 400},          // 11 digits
      {"from=4294967296&to=4294967297", 400},  // 2^32
      {"from=4294967295&to=4294967295", 400},  // fits 32 bits, beyond the replay
      {"fromx=1&to=2", 400},                   // another key: `from` missing
      {"from=1&from=2&to=3", 400},             // a key twice
      {"from=5&to=3", 400},                    // reversed
      {"from=0&to=1", 400},                    // ticks start at 1
      {"from=1&to=602", 400},                  // over kMaxFramesPerRequest
      {past_end.c_str(), 400},                 // past the last tick + 1
      {"from=1&to=2", 200},
      {"to=3&from=2", 200},              // either order
      {"from=0000000001&to=2", 200},     // 10 digits
      {"x=1&from=1&to=2&fromx=3", 200},  // other keys are not read
  };
  std::uint64_t refused = 0;
  for (const Case& c : cases) {
    const RecordingsReply reply = get(std::string(kId) + "/frames", c.query);
    EXPECT_EQ(reply.status, c.status) << c.query << ": " << reply.body;
    if (c.status == 400) ++refused;
    EXPECT_EQ(routes_.bad_requests(), refused) << c.query;
    if (c.status == 200) {
      EXPECT_EQ(reply.content_type, "application/json");
      EXPECT_TRUE(reply.body.starts_with("{\"first_tick\":")) << reply.body.substr(0, 80);
    }
  }
  // The whole replay's last tick is the end of a range that reaches it.
  const RecordingsReply tail = get(std::string(kId) + "/frames",
                                   "from=" + last + "&to=" + std::to_string(done.ticks_total + 1));
  EXPECT_EQ(tail.status, 200u) << tail.body;
  EXPECT_EQ(query_tick("from=4294967295", "from"), 4294967295u);
  EXPECT_EQ(query_tick("a=1&from=7", "from"), 7u);
  EXPECT_EQ(query_tick("from=7&from=7", "from"), std::nullopt);
  EXPECT_EQ(query_tick("from", "from"), std::nullopt);
}

TEST_F(ReplayRoutesTest, BeyondMaxReplaysIsBusyAndARunningReplayCancelsFreeingItsWorker) {
  // The one worker holds kId after its 10th step: running; kOtherId queued behind it.
  const RecordingsReply started = post(std::string(kId) + "/replay");
  ASSERT_EQ(started.status, 200u);
  ASSERT_TRUE(hold_.wait_held());
  EXPECT_NE(get(kId).body.find("\"state\":\"running\",\"ticks_done\":10,"), std::string::npos)
      << get(kId).body;
  const RecordingsReply queued = post(std::string(kOtherId) + "/replay");
  EXPECT_EQ(queued.status, 200u);
  EXPECT_NE(queued.body.find("\"state\":\"queued\""), std::string::npos) << queued.body;

  // A third: max_replays (2) are queued or running.
  const RecordingsReply busy = post(std::string(kThirdId) + "/replay");
  EXPECT_EQ(busy.status, 503u);
  EXPECT_EQ(busy.body,
            "busy: 2 replays are queued or running (dashboard.max_replays); ask again when one "
            "is done\n");
  EXPECT_EQ(jobs_.refused_busy(), 1u);
  EXPECT_EQ(routes_.bad_requests(), 0u);
  EXPECT_EQ(get(kThirdId).body,
            std::string("{\"id\":\"") + kThirdId + "\",\"job\":null,\"summary\":null}");

  // Cancelled mid-run: it stops after the step it was held at, and gives no frames.
  const RecordingsReply cancelled = post(std::string(kId) + "/cancel");
  EXPECT_EQ(cancelled.status, 200u);
  EXPECT_EQ(cancelled.body, "{\"cancelled\":true}");
  hold_.release();
  const ReplayJobStatus stopped = wait_finished(kId);
  EXPECT_EQ(stopped.state, ReplayJobState::Cancelled);
  EXPECT_EQ(stopped.ticks_done, 10u);
  EXPECT_GT(stopped.ticks_total, 500u);
  EXPECT_NE(get(kId).body.find("\"state\":\"cancelled\""), std::string::npos);
  EXPECT_EQ(get(std::string(kId) + "/frames", "from=1&to=2").status, 409u);
  EXPECT_EQ(post(std::string(kId) + "/cancel").status, 404u) << "nothing left to cancel";

  // The worker is free: the queued one runs to its end, then a new one does.
  const ReplayJobStatus other = wait_finished(kOtherId);
  EXPECT_EQ(other.state, ReplayJobState::Done) << other.error;
  ASSERT_EQ(post(std::string(kThirdId) + "/replay").status, 200u);
  const ReplayJobStatus third = wait_finished(kThirdId);
  EXPECT_EQ(third.state, ReplayJobState::Done) << third.error;
  EXPECT_EQ(third.ticks_done, third.ticks_total);
  EXPECT_EQ(get(std::string(kThirdId) + "/frames", "from=1&to=2").status, 200u);
}

TEST_F(ReplayRoutesTest, AReplayedKillIsInTheFramesAsTheMatchToldItsPlayers) {
  const std::vector<wire::Kill>& kills = recorded().kills;
  ASSERT_FALSE(kills.empty()) << "the script makes the players kill each other";
  hold_.release();
  ASSERT_EQ(post(std::string(kId) + "/replay").status, 200u);
  const ReplayJobStatus done = wait_finished(kId);
  ASSERT_EQ(done.state, ReplayJobState::Done) << done.error;
  const std::string summary = get(kId).body;
  EXPECT_NE(summary.find("\"kills\":" + std::to_string(kills.size()) + ",\"players\":["),
            std::string::npos)
      << summary;

  // Every kill, in order, in the frames the page reads (kMaxFramesPerRequest at a time), with
  // its killer, victim, weapon and the tick its event said, in the frame of that tick's step.
  std::string feed;
  for (std::uint32_t first = 1; first <= done.ticks_total; first += kMaxFramesPerRequest) {
    const std::uint32_t end = std::min(first + kMaxFramesPerRequest, done.ticks_total + 1);
    const RecordingsReply frames =
        get(std::string(kId) + "/frames",
            "from=" + std::to_string(first) + "&to=" + std::to_string(end));
    ASSERT_EQ(frames.status, 200u) << frames.body;
    feed += frames.body;
  }
  std::size_t at = 0;
  for (const wire::Kill& kill : kills) {
    const std::string expected = "{\"killer\":" + std::to_string(kill.killer_entity_id()) +
                                 ",\"victim\":" + std::to_string(kill.victim_entity_id()) +
                                 ",\"weapon\":" + std::to_string(kill.weapon()) +
                                 ",\"tick\":" + std::to_string(kill.tick()) + "}";
    const std::size_t found = feed.find(expected, at);
    ASSERT_NE(found, std::string::npos) << expected << " after byte " << at;
    // In the frame of the step it happened in: the event's tick or the next.
    const std::size_t frame = feed.rfind("{\"tick\":", found);
    ASSERT_NE(frame, std::string::npos);
    const std::uint32_t step = static_cast<std::uint32_t>(std::stoul(feed.substr(frame + 8, 12)));
    EXPECT_TRUE(step == kill.tick() || step == kill.tick() + 1) << expected << " in " << step;
    at = found + expected.size();
  }
  std::size_t in_feed = 0;
  for (std::size_t i = feed.find("{\"killer\":"); i != std::string::npos;
       i = feed.find("{\"killer\":", i + 1)) {
    ++in_feed;
  }
  EXPECT_EQ(in_feed, kills.size());
}

}  // namespace
}  // namespace ricochet::server::replay_routes_test
