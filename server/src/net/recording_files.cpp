#include "recording_files.h"

#include <fcntl.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string_view>
#include <system_error>
#include <utility>

#include "durable_files.h"

namespace ricochet::server {

namespace {

constexpr std::string_view kPartSuffix = ".rcr.part";

}  // namespace

RecordingFiles::RecordingFiles(std::filesystem::path directory, std::size_t max_queued_bytes)
    : directory_(std::move(directory)), max_queued_bytes_(max_queued_bytes) {
  keep_interrupted();
  thread_ = std::thread([this] { run(); });
}

RecordingFiles::~RecordingFiles() {
  stop();
}

std::string RecordingFiles::part_name(std::uint32_t match_id, std::int64_t started_unix_ms) {
  std::string name = "match-";
  name += std::to_string(match_id);
  name += '-';
  name += std::to_string(started_unix_ms);
  name += kPartSuffix;
  return name;
}

std::string RecordingFiles::file_name(std::uint32_t match_id, std::int64_t ended_unix_ms) {
  std::string name = "match-";
  name += std::to_string(match_id);
  name += '-';
  name += std::to_string(ended_unix_ms);
  name += ".rcr";
  return name;
}

std::string RecordingFiles::interrupted_name(const std::string& part_name) {
  std::string name = part_name;
  if (name.ends_with(kPartSuffix)) name.resize(name.size() - kPartSuffix.size());
  name += ".interrupted.rcr";
  return name;
}

void RecordingFiles::keep_interrupted() {
  std::error_code error;
  if (!std::filesystem::is_directory(directory_, error)) return;  // nothing recorded here yet
  std::vector<std::filesystem::path> parts;
  std::filesystem::directory_iterator it(directory_, error);
  for (; !error && it != std::filesystem::directory_iterator(); it.increment(error)) {
    const std::string name = it->path().filename().string();
    std::error_code type_error;
    if (name.ends_with(kPartSuffix) && it->is_regular_file(type_error)) parts.push_back(it->path());
  }
  if (error) {
    spdlog::error("cannot look for interrupted recordings in {}: {}", directory_.string(),
                  error.message());
  }
  bool renamed = false;
  for (const std::filesystem::path& part : parts) {
    const std::filesystem::path target = directory_ / interrupted_name(part.filename().string());
    const std::uintmax_t size = std::filesystem::file_size(part, error);
    if (std::filesystem::exists(target, error)) {
      spdlog::error("recording {} was interrupted; {} exists, so it stays as it is", part.string(),
                    target.string());
      continue;
    }
    std::filesystem::rename(part, target, error);
    if (error) {
      spdlog::error("recording {} was interrupted and cannot be renamed to {}: {}", part.string(),
                    target.string(), error.message());
      continue;
    }
    renamed = true;
    interrupted_.fetch_add(1);
    spdlog::warn(
        "recording {} was interrupted (the server stopped without ending its match); kept as {} "
        "({} bytes, readable to its last whole chunk: ricochet-replay says where it stops)",
        part.string(), target.string(), size);
  }
  if (renamed) {
    if (const std::string sync_error = sync_directory(directory_); !sync_error.empty()) {
      spdlog::error("interrupted recordings: {}", sync_error);
    }
  }
}

bool RecordingFiles::has_room() const {
  return queued_bytes_.load() <= max_queued_bytes_;
}

void RecordingFiles::append(const std::string& part_name, std::vector<std::uint8_t> bytes) {
  if (bytes.empty()) return;
  const std::lock_guard lock(mutex_);
  if (stopping_) return;  // finish() says it; the .part stays for the next start
  queued_bytes_.fetch_add(bytes.size());
  queue_.push_back(Job{part_name, {}, std::move(bytes)});
  wake_.notify_one();
}

void RecordingFiles::finish(const std::string& part_name, const std::string& final_name,
                            std::vector<std::uint8_t> bytes) {
  {
    const std::lock_guard lock(mutex_);
    if (!stopping_) {
      queued_bytes_.fetch_add(bytes.size());
      queue_.push_back(Job{part_name, final_name, std::move(bytes)});
      wake_.notify_one();
      return;
    }
  }
  failed_.fetch_add(1);
  spdlog::error("recording {} not finished: the server is stopping", final_name);
}

void RecordingFiles::stop() {
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
    wake_.notify_one();
  }
  if (thread_.joinable()) thread_.join();
}

void RecordingFiles::run() {
  for (;;) {
    Job job;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
      if (queue_.empty()) break;  // stopping, and everything is written
      job = std::move(queue_.front());
      queue_.pop_front();
    }
    write(job);
    queued_bytes_.fetch_sub(job.bytes.size());
  }
  for (auto& [name, stream] : streams_) {
    if (stream.fd < 0) continue;
    ::fsync(stream.fd);
    ::close(stream.fd);
    spdlog::warn("recording {} was not finished; it stays as it is ({} bytes)",
                 (directory_ / name).string(), stream.bytes);
  }
  streams_.clear();
}

bool RecordingFiles::open(const std::string& name, Stream& stream) {
  if (stream.fd >= 0) return true;
  std::error_code error;
  std::filesystem::create_directories(directory_, error);
  if (error) {
    fail(name, stream, "cannot create " + directory_.string() + ": " + error.message());
    return false;
  }
  const std::filesystem::path path = directory_ / name;
  stream.fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (stream.fd < 0) {
    fail(name, stream, "cannot create " + path.string() + ": " + errno_text());
    return false;
  }
  if (const std::string sync_error = sync_directory(directory_); !sync_error.empty()) {
    spdlog::warn("recording {}: {}", path.string(), sync_error);
  }
  return true;
}

void RecordingFiles::fail(const std::string& name, Stream& stream, const std::string& what) {
  stream.failed = true;
  if (stream.fd >= 0) ::close(stream.fd);
  stream.fd = -1;
  spdlog::error("recording {} stops at {} bytes: {}", (directory_ / name).string(), stream.bytes,
                what);
}

void RecordingFiles::write(const Job& job) {
  Stream& stream = streams_[job.part_name];
  const bool last = !job.final_name.empty();
  if (!stream.failed && open(job.part_name, stream)) {
    if (std::string error = write_all(stream.fd, job.bytes); !error.empty()) {
      fail(job.part_name, stream, error);
    } else if (::fsync(stream.fd) != 0) {
      fail(job.part_name, stream, "fsync failed: " + errno_text());
    } else {
      stream.bytes += job.bytes.size();
    }
  }
  if (!last) return;
  const std::filesystem::path part = directory_ / job.part_name;
  const Stream done = stream;
  streams_.erase(job.part_name);
  std::error_code error;
  if (done.failed) {
    failed_.fetch_add(1);
    const std::filesystem::path kept = directory_ / interrupted_name(job.part_name);
    std::filesystem::rename(part, kept, error);
    spdlog::error("recording {} not written whole; {}", job.final_name,
                  error ? "what was written stays in " + part.string()
                        : "what was written is in " + kept.string());
    return;
  }
  ::close(done.fd);
  const std::filesystem::path target = directory_ / job.final_name;
  std::filesystem::rename(part, target, error);
  if (error) {
    failed_.fetch_add(1);
    spdlog::error("recording {} cannot be renamed to {}: {}", part.string(), target.string(),
                  error.message());
    return;
  }
  if (const std::string sync_error = sync_directory(directory_); !sync_error.empty()) {
    spdlog::warn("recording {}: {}", target.string(), sync_error);
  }
  written_.fetch_add(1);
  written_bytes_.fetch_add(done.bytes);
  spdlog::info("recording {} written ({} bytes)", target.string(), done.bytes);
}

}  // namespace ricochet::server
