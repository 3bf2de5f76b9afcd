// Replays on their own worker threads (replay_jobs.h): more replays than allowed are refused as
// busy; a queued or running job cancels; results are cached, least recently used dropped first
// once over the budget; a corrupt recording fails with why. The clock is a counter; the tests
// wait for the workers on a condition (bounded), never on time.

#include "replay_jobs.h"

#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "scripted_recording.h"

namespace ricochet::server::replay_jobs_test {
namespace {

/// Recordings by id, and a gate every load waits at until opened.
class Source {
 public:
  explicit Source(std::vector<std::uint8_t> bytes) : bytes_(std::move(bytes)) {}
  ReplayJobs::Source function() {
    return [this](const std::string& id) -> std::variant<std::vector<std::uint8_t>, std::string> {
      std::unique_lock lock(mutex_);
      ++waiting_;
      changed_.notify_all();
      changed_.wait(lock, [&] { return open_; });
      --waiting_;
      if (id == "match-9-9") return std::string("no recording match-9-9");
      if (id == "match-8-8") return std::vector<std::uint8_t>(bytes_.begin(), bytes_.begin() + 50);
      return bytes_;
    };
  }
  void open() {
    const std::lock_guard lock(mutex_);
    open_ = true;
    changed_.notify_all();
  }
  /// Until `count` loads wait at the gate (bounded: false after 30 s).
  bool wait_for_waiting(int count) {
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, std::chrono::seconds(30), [&] { return waiting_ == count; });
  }

 private:
  std::vector<std::uint8_t> bytes_;
  std::mutex mutex_;
  std::condition_variable changed_;
  bool open_ = false;
  int waiting_ = 0;
};

/// Until the job is no longer queued or running (bounded: its last status after 30 s).
ReplayJobStatus wait_done(ReplayJobs& jobs, const std::string& id) {
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  for (;;) {
    const auto status = jobs.status(id);
    if (!status) return {};
    if ((status->state != ReplayJobState::Queued && status->state != ReplayJobState::Running) ||
        std::chrono::steady_clock::now() > give_up) {
      return *status;
    }
    std::this_thread::yield();
  }
}

TEST(ReplayJobsTest, MoreReplaysThanAllowedAreRefusedAsBusy) {
  Source source(web_test::scripted_recording(300));
  double now_s = 100;
  ReplayJobs jobs({.workers = 1, .max_replays = 2, .memory_mb = 16}, source.function(),
                  [&] { return now_s += 1; });
  std::string busy;
  ASSERT_TRUE(jobs.start("match-1-1", busy).has_value());
  ASSERT_TRUE(source.wait_for_waiting(1));  // the worker holds the first
  const auto second = jobs.start("match-2-2", busy);
  ASSERT_TRUE(second.has_value());
  EXPECT_EQ(second->state, ReplayJobState::Queued);
  EXPECT_EQ(second->queued_at_s, 102);
  EXPECT_EQ(jobs.status("match-1-1")->state, ReplayJobState::Running);

  EXPECT_FALSE(jobs.start("match-3-3", busy).has_value());
  EXPECT_EQ(busy,
            "busy: 2 replays are queued or running (dashboard.max_replays); ask again when one is "
            "done");
  EXPECT_EQ(jobs.refused_busy(), 1u);
  EXPECT_FALSE(jobs.status("match-3-3").has_value());
  // Asking again for a job already queued is no new job.
  EXPECT_EQ(jobs.start("match-2-2", busy)->state, ReplayJobState::Queued);
  EXPECT_EQ(busy, "");

  source.open();
  EXPECT_EQ(wait_done(jobs, "match-1-1").state, ReplayJobState::Done);
  const ReplayJobStatus done = wait_done(jobs, "match-2-2");
  EXPECT_EQ(done.state, ReplayJobState::Done);
  EXPECT_EQ(done.ticks_done, done.ticks_total);
  EXPECT_GT(done.ticks_total, 250u);
  ASSERT_NE(jobs.result("match-2-2"), nullptr);
  EXPECT_EQ(jobs.result("match-2-2")->last_tick, done.ticks_total);
  EXPECT_TRUE(jobs.start("match-3-3", busy).has_value()) << "room again: " << busy;
  EXPECT_EQ(
      replay_job_json(done),
      "{\"id\":\"match-2-2\",\"state\":\"done\",\"ticks_done\":" + std::to_string(done.ticks_done) +
          ",\"ticks_total\":" + std::to_string(done.ticks_total) + ",\"error\":null}");
}

TEST(ReplayJobsTest, QueuedAndRunningJobsCancelAndABadRecordingFailsWithWhy) {
  Source source(web_test::scripted_recording(300));
  ReplayJobs jobs({.workers = 1, .max_replays = 4, .memory_mb = 16}, source.function(),
                  [] { return 0.0; });
  std::string busy;
  jobs.start("match-1-1", busy);
  ASSERT_TRUE(source.wait_for_waiting(1));
  jobs.start("match-2-2", busy);
  EXPECT_TRUE(jobs.cancel("match-2-2"));
  EXPECT_EQ(jobs.status("match-2-2")->state, ReplayJobState::Cancelled);
  EXPECT_TRUE(jobs.cancel("match-1-1"));  // running: stops at its first step
  EXPECT_FALSE(jobs.cancel("match-5-5"));
  jobs.start("match-8-8", busy);
  jobs.start("match-9-9", busy);
  source.open();
  EXPECT_EQ(wait_done(jobs, "match-1-1").state, ReplayJobState::Cancelled);
  EXPECT_EQ(jobs.result("match-1-1"), nullptr);
  const ReplayJobStatus cut = wait_done(jobs, "match-8-8");
  EXPECT_EQ(cut.state, ReplayJobState::Failed);
  EXPECT_NE(cut.error.find("unreadable: truncated at byte 50 in chunk 0 (header)"),
            std::string::npos)
      << cut.error;
  EXPECT_NE(replay_job_json(cut).find("\"state\":\"failed\""), std::string::npos);
  EXPECT_EQ(wait_done(jobs, "match-9-9").error, "no recording match-9-9");
  // A cancelled job starts again when asked.
  EXPECT_EQ(jobs.start("match-2-2", busy)->state, ReplayJobState::Queued);
  EXPECT_EQ(wait_done(jobs, "match-2-2").state, ReplayJobState::Done);
}

TEST(ReplayJobsTest, ResultsAreCachedAndTheLeastRecentlyUsedDroppedOverTheBudget) {
  Source source(web_test::scripted_recording(300));
  source.open();
  // 1 MiB in all: 512 KiB of results kept, 256 KiB for each of the two workers' frames.
  ReplayJobs jobs({.workers = 2, .max_replays = 4, .memory_mb = 1}, source.function(),
                  [] { return 0.0; });
  std::string busy;
  jobs.start("match-1-1", busy);
  ASSERT_EQ(wait_done(jobs, "match-1-1").state, ReplayJobState::Done);
  const std::size_t one = jobs.cached_bytes();
  ASSERT_GT(one, 20'000u);
  ASSERT_LT(one, 256u * 1024);
  const auto first = jobs.result("match-1-1");
  const std::size_t fit = (512u * 1024) / one;  // results the cache holds
  for (std::size_t i = 2; i <= fit + 2; ++i) {
    const std::string id = "match-" + std::to_string(i) + "-1";
    jobs.start(id, busy);
    ASSERT_EQ(wait_done(jobs, id).state, ReplayJobState::Done) << id;
    jobs.result("match-1-1");  // kept in use: never the least recently used
  }
  EXPECT_LE(jobs.cached_bytes(), 512u * 1024);
  EXPECT_GE(jobs.evicted(), 1u);
  EXPECT_EQ(jobs.result("match-1-1"), first) << "the one in use stays, the same result";
  EXPECT_FALSE(jobs.status("match-2-1").has_value()) << "the least recently used went first";
  // Asking for it again replays it again.
  EXPECT_EQ(jobs.start("match-2-1", busy)->state, ReplayJobState::Queued);
}

TEST(ReplayJobsTest, TheConfigIsValidatedNamingEachKey) {
  EXPECT_TRUE(ReplayJobsConfig{}.validate().empty());
  const auto problems =
      ReplayJobsConfig{.workers = 0, .max_replays = 100, .memory_mb = 8}.validate();
  ASSERT_EQ(problems.size(), 3u);
  EXPECT_EQ(problems[0], "dashboard.replay_workers must be 1..8, got 0");
  EXPECT_EQ(problems[1], "dashboard.max_replays must be 1..64, got 100");
  EXPECT_EQ(problems[2], "dashboard.replay_memory_mb must be 16..65536, got 8");
  const ReplayJobsConfig fewer_jobs_than_workers{.workers = 4, .max_replays = 2};
  EXPECT_EQ(fewer_jobs_than_workers.validate(),
            std::vector<std::string>{"dashboard.max_replays must be 4..64, got 2"});
}

}  // namespace
}  // namespace ricochet::server::replay_jobs_test
