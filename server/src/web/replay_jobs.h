#pragma once
/// Replays for the dashboard, on a small pool of worker threads of their own (never a match's
/// strand): a job per recording re-simulates it into frames (replay_frames.h), its progress
/// readable and cancelable while it runs, its result kept in a bounded cache, least recently
/// used dropped first.
///
/// Bounds ([dashboard] in the config): `workers` threads; at most `max_replays` jobs queued or
/// running (one more is refused as busy, with a clear answer, never queued without end); and
/// `memory_mb` in all: the frames of each running job (at most `workers` run) stay within
/// memory / (2 * workers) (a job needing more fails saying so) and the cache's results within
/// memory / 2. The recording a running job decodes is on top of that (about 10x its file's
/// size). match-bench measures 3.2 MiB of frames per 16-player minute.
///
/// Time is passed in (a clock in seconds): it only dates the jobs.

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "replay_frames.h"

namespace ricochet::server {

/// The ranges of ReplayJobsConfig's fields (and of their [dashboard] keys).
inline constexpr int kMaxReplayWorkers = 8;
inline constexpr int kMaxReplaysAtOnce = 64;
inline constexpr int kMinReplayMemoryMb = 16;
inline constexpr int kMaxReplayMemoryMb = 65536;

struct ReplayJobsConfig {
  int workers = 1;      ///< threads replaying, 1..kMaxReplayWorkers
  int max_replays = 4;  ///< jobs queued or running at once, workers..kMaxReplaysAtOnce
  int memory_mb = 256;  ///< frames of running jobs and cached results together, MiB

  /// Empty when valid; otherwise every problem, naming the key, its range and what came.
  std::vector<std::string> validate() const;
};

enum class ReplayJobState : std::uint8_t { Queued, Running, Done, Failed, Cancelled };
inline constexpr std::size_t kReplayJobStateCount =
    static_cast<std::size_t>(ReplayJobState::Cancelled) + 1;
const char* name(ReplayJobState state);

struct ReplayJobStatus {
  std::string id;
  ReplayJobState state = ReplayJobState::Queued;
  std::uint32_t ticks_done = 0;
  std::uint32_t ticks_total = 0;  ///< known once the recording is read (0 before)
  std::string error;              ///< Failed: why
  double queued_at_s = 0;         ///< by the clock passed in
  double finished_at_s = 0;       ///< Done, Failed, Cancelled
};
/// {"id","state","ticks_done","ticks_total","error"}.
std::string replay_job_json(const ReplayJobStatus& status);

class ReplayJobs {
 public:
  /// Finished jobs remembered at most (their status, and the results within the budget).
  static constexpr std::size_t kKeptJobs = 256;
  /// The bytes of the recording `id` names (the caller checked the id), or why not.
  using Source =
      std::function<std::variant<std::vector<std::uint8_t>, std::string>(const std::string& id)>;
  using Clock = std::function<double()>;
  /// Called on a worker after each step of the replay of `id` (ReplayProgress::after_step).
  using StepHook = std::function<void(const std::string& id, std::uint32_t tick)>;

  /// Starts the workers. `config` must be valid. `after_step`, when set, is every job's hook
  /// (tests hold a worker mid-replay with it).
  ReplayJobs(const ReplayJobsConfig& config, Source source, Clock clock_s,
             StepHook after_step = {});
  /// Stops every job and joins the workers.
  ~ReplayJobs();
  ReplayJobs(const ReplayJobs&) = delete;
  ReplayJobs& operator=(const ReplayJobs&) = delete;

  /// Thread-safe. The job of `id`: the cached result (Done), the one queued or running, or a new
  /// one queued; a failed or cancelled job is started again. Busy: nothing when max_replays are
  /// queued or running already, with `busy` saying so.
  std::optional<ReplayJobStatus> start(const std::string& id, std::string& busy);
  /// Thread-safe: the job's status; nothing for an id never started or dropped from the cache.
  std::optional<ReplayJobStatus> status(const std::string& id) const;
  /// Thread-safe: a queued job is dropped, a running one stops at its next step. False when no
  /// job of `id` is queued or running.
  bool cancel(const std::string& id);
  /// Thread-safe: the frames of a Done job (and marks it used); null otherwise.
  std::shared_ptr<const ReplayFrames> result(const std::string& id);

  std::size_t cached_bytes() const;
  std::uint64_t refused_busy() const;
  std::uint64_t evicted() const;

 private:
  struct Job {
    ReplayJobStatus status;
    std::shared_ptr<ReplayProgress> progress;
    std::shared_ptr<const ReplayFrames> frames;  ///< Done
    std::size_t bytes = 0;                       ///< of frames
  };
  void work();
  void run(const std::string& id, std::shared_ptr<ReplayProgress> progress);
  void finish(const std::string& id, std::variant<ReplayFrames, std::string> outcome);
  /// Drops least recently used results until the cache is within its budget. Holds mutex_.
  void evict();
  ReplayJobStatus snapshot(const Job& job) const;
  std::size_t active() const;

  const ReplayJobsConfig config_;
  const std::size_t job_bytes_;    ///< one job's frames at most
  const std::size_t cache_bytes_;  ///< the results kept at most
  const Source source_;
  const Clock clock_;
  const StepHook after_step_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::map<std::string, Job> jobs_;
  std::deque<std::string> queue_;
  /// Finished jobs (Done, Failed, Cancelled), most recently used first; at most kKeptJobs.
  std::list<std::string> used_;
  std::size_t cached_ = 0;  ///< bytes of the Done jobs' frames
  std::uint64_t refused_busy_ = 0;
  std::uint64_t evicted_ = 0;
  std::vector<std::thread> workers_;  ///< last: start once everything above exists
};

}  // namespace ricochet::server
