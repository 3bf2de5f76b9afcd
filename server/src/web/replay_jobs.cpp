/// Replays on worker threads, bounded, cancelable, cached (replay_jobs.h).

#include "replay_jobs.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <utility>

#include "ricochet/tools/json_text.h"

namespace ricochet::server {

std::vector<std::string> ReplayJobsConfig::validate() const {
  std::vector<std::string> problems;
  const auto range = [&](const char* key, int value, int min, int max) {
    if (value >= min && value <= max) return;
    problems.push_back(std::string("dashboard.") + key + " must be " + std::to_string(min) + ".." +
                       std::to_string(max) + ", got " + std::to_string(value));
  };
  range("replay_workers", workers, 1, kMaxReplayWorkers);
  range("max_replays", max_replays, std::clamp(workers, 1, kMaxReplayWorkers), kMaxReplaysAtOnce);
  range("replay_memory_mb", memory_mb, kMinReplayMemoryMb, kMaxReplayMemoryMb);
  return problems;
}

const char* name(ReplayJobState state) {
  switch (state) {
    case ReplayJobState::Queued:
      return "queued";
    case ReplayJobState::Running:
      return "running";
    case ReplayJobState::Done:
      return "done";
    case ReplayJobState::Failed:
      return "failed";
    case ReplayJobState::Cancelled:
      return "cancelled";
  }
  return "unknown";
}

std::string replay_job_json(const ReplayJobStatus& status) {
  std::string out = "{\"id\":" + tools::json_string(status.id);
  out += ",\"state\":\"";
  out += name(status.state);
  out += "\",\"ticks_done\":" + std::to_string(status.ticks_done);
  out += ",\"ticks_total\":" + std::to_string(status.ticks_total);
  out += ",\"error\":" + (status.state == ReplayJobState::Failed ? tools::json_string(status.error)
                                                                 : std::string("null"));
  out += '}';
  return out;
}

ReplayJobs::ReplayJobs(const ReplayJobsConfig& config, Source source, Clock clock_s,
                       StepHook after_step)
    : config_(config),
      job_bytes_(std::size_t(config.memory_mb) * (1u << 20) / (2 * std::size_t(config.workers))),
      cache_bytes_(std::size_t(config.memory_mb) * (1u << 20) / 2),
      source_(std::move(source)),
      clock_(std::move(clock_s)),
      after_step_(std::move(after_step)) {
  for (int i = 0; i < config_.workers; ++i) workers_.emplace_back([this] { work(); });
}

ReplayJobs::~ReplayJobs() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
    for (auto& [id, job] : jobs_) {
      if (job.progress) job.progress->stop.store(true);
    }
  }
  wake_.notify_all();
  for (std::thread& worker : workers_) worker.join();
}

std::size_t ReplayJobs::active() const {
  return static_cast<std::size_t>(std::count_if(jobs_.begin(), jobs_.end(), [](const auto& each) {
    const ReplayJobState state = each.second.status.state;
    return state == ReplayJobState::Queued || state == ReplayJobState::Running;
  }));
}

ReplayJobStatus ReplayJobs::snapshot(const Job& job) const {
  ReplayJobStatus status = job.status;
  if (job.progress && status.state == ReplayJobState::Running) {
    status.ticks_done = job.progress->ticks_done.load(std::memory_order_relaxed);
  }
  return status;
}

std::optional<ReplayJobStatus> ReplayJobs::start(const std::string& id, std::string& busy) {
  busy.clear();
  const std::lock_guard lock(mutex_);
  const auto it = jobs_.find(id);
  if (it != jobs_.end()) {
    const ReplayJobState state = it->second.status.state;
    if (state == ReplayJobState::Done) {
      used_.remove(id);
      used_.push_front(id);
    }
    if (state != ReplayJobState::Failed && state != ReplayJobState::Cancelled)
      return snapshot(it->second);
  }
  if (active() >= static_cast<std::size_t>(config_.max_replays)) {
    ++refused_busy_;
    busy = "busy: " + std::to_string(config_.max_replays) +
           " replays are queued or running (dashboard.max_replays); ask again when one is done";
    return std::nullopt;
  }
  if (it != jobs_.end()) {
    used_.remove(id);
    jobs_.erase(it);
  }
  Job& job = jobs_[id];
  job.status.id = id;
  job.status.queued_at_s = clock_();
  job.progress = std::make_shared<ReplayProgress>();
  if (after_step_) {
    job.progress->after_step = [hook = after_step_, id](std::uint32_t tick) { hook(id, tick); };
  }
  queue_.push_back(id);
  wake_.notify_one();
  return snapshot(job);
}

std::optional<ReplayJobStatus> ReplayJobs::status(const std::string& id) const {
  const std::lock_guard lock(mutex_);
  const auto it = jobs_.find(id);
  if (it == jobs_.end()) return std::nullopt;
  return snapshot(it->second);
}

bool ReplayJobs::cancel(const std::string& id) {
  const std::lock_guard lock(mutex_);
  const auto it = jobs_.find(id);
  if (it == jobs_.end()) return false;
  Job& job = it->second;
  if (job.status.state == ReplayJobState::Queued) {
    std::erase(queue_, id);
    job.status.state = ReplayJobState::Cancelled;
    job.status.finished_at_s = clock_();
    job.progress.reset();
    used_.push_front(id);
    evict();
    return true;
  }
  if (job.status.state != ReplayJobState::Running) return false;
  job.progress->stop.store(true);  // finish() marks it cancelled
  return true;
}

std::shared_ptr<const ReplayFrames> ReplayJobs::result(const std::string& id) {
  const std::lock_guard lock(mutex_);
  const auto it = jobs_.find(id);
  if (it == jobs_.end() || it->second.status.state != ReplayJobState::Done) return nullptr;
  used_.remove(id);
  used_.push_front(id);
  return it->second.frames;
}

std::size_t ReplayJobs::cached_bytes() const {
  const std::lock_guard lock(mutex_);
  return cached_;
}

std::uint64_t ReplayJobs::refused_busy() const {
  const std::lock_guard lock(mutex_);
  return refused_busy_;
}

std::uint64_t ReplayJobs::evicted() const {
  const std::lock_guard lock(mutex_);
  return evicted_;
}

void ReplayJobs::work() {
  for (;;) {
    std::string id;
    std::shared_ptr<ReplayProgress> progress;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
      if (stopping_) return;
      id = std::move(queue_.front());
      queue_.pop_front();
      Job& job = jobs_.at(id);
      job.status.state = ReplayJobState::Running;
      progress = job.progress;
    }
    run(id, std::move(progress));
  }
}

void ReplayJobs::run(const std::string& id, std::shared_ptr<ReplayProgress> progress) {
  auto bytes = source_(id);
  if (auto* bad = std::get_if<std::string>(&bytes)) {
    finish(id, std::move(*bad));
    return;
  }
  auto read = read_recording(std::get<std::vector<std::uint8_t>>(bytes));
  std::get<std::vector<std::uint8_t>>(bytes) = {};
  if (const auto* bad = std::get_if<RecordingError>(&read)) {
    finish(id, "unreadable: " + bad->message + " (byte " + std::to_string(bad->offset) + ")");
    return;
  }
  const Recording& recording = std::get<Recording>(read);
  progress->ticks_total = recording.ticks.empty() ? 0 : recording.ticks.back().tick;
  {
    const std::lock_guard lock(mutex_);
    jobs_.at(id).status.ticks_total = progress->ticks_total;
  }
  finish(id, replay_frames(recording, *progress, job_bytes_));
}

void ReplayJobs::finish(const std::string& id, std::variant<ReplayFrames, std::string> outcome) {
  const std::lock_guard lock(mutex_);
  Job& job = jobs_.at(id);
  job.status.finished_at_s = clock_();
  job.status.ticks_done = job.progress->ticks_done.load();
  const bool stopped = job.progress->stop.load();
  job.progress.reset();
  if (auto* frames = std::get_if<ReplayFrames>(&outcome)) {
    job.status.state = ReplayJobState::Done;
    job.bytes = frames->bytes();
    job.frames = std::make_shared<const ReplayFrames>(std::move(*frames));
    cached_ += job.bytes;
  } else if (stopped) {
    job.status.state = ReplayJobState::Cancelled;
  } else {
    job.status.state = ReplayJobState::Failed;
    job.status.error = std::move(std::get<std::string>(outcome));
    spdlog::warn("replay of recording {} failed: {}", id, job.status.error);
  }
  used_.push_front(id);
  evict();
}

void ReplayJobs::evict() {
  while (!used_.empty() && (cached_ > cache_bytes_ || used_.size() > kKeptJobs)) {
    const std::string id = used_.back();
    used_.pop_back();
    const auto it = jobs_.find(id);
    if (it == jobs_.end()) continue;
    cached_ -= it->second.bytes;
    if (it->second.frames) ++evicted_;
    jobs_.erase(it);
  }
}

}  // namespace ricochet::server
