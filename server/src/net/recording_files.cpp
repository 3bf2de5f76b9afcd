#include "recording_files.h"

#include <spdlog/spdlog.h>

#include <fstream>
#include <system_error>
#include <utility>

namespace ricochet::server {

std::string write_file_atomically(const std::filesystem::path& directory, const std::string& name,
                                  std::span<const std::uint8_t> bytes) {
  std::error_code error;
  std::filesystem::create_directories(directory, error);
  if (error) return "cannot create " + directory.string() + ": " + error.message();
  const std::filesystem::path target = directory / name;
  const std::filesystem::path temporary = directory / ("." + name + ".tmp");
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) return "cannot open " + temporary.string() + " for writing";
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
    out.flush();
    if (!out) {
      out.close();
      std::filesystem::remove(temporary, error);
      return "cannot write " + std::to_string(bytes.size()) + " bytes to " + temporary.string();
    }
  }
  std::filesystem::rename(temporary, target, error);
  if (error) {
    std::string message = "cannot rename " + temporary.string() + " to " + target.string();
    message += ": ";
    message += error.message();
    std::filesystem::remove(temporary, error);
    return message;
  }
  return {};
}

RecordingFiles::RecordingFiles(std::filesystem::path directory)
    : directory_(std::move(directory)), thread_([this] { run(); }) {}

RecordingFiles::~RecordingFiles() {
  stop();
}

std::string RecordingFiles::file_name(std::uint32_t match_id, std::int64_t ended_unix_ms) {
  std::string name = "match-";
  name += std::to_string(match_id);
  name += '-';
  name += std::to_string(ended_unix_ms);
  name += ".rcr";
  return name;
}

void RecordingFiles::write(std::uint32_t match_id, std::int64_t ended_unix_ms,
                           std::vector<std::uint8_t> bytes) {
  std::string name = file_name(match_id, ended_unix_ms);
  {
    const std::lock_guard lock(mutex_);
    if (!stopping_) {
      queue_.push_back(Job{std::move(name), std::move(bytes)});
      wake_.notify_one();
      return;
    }
  }
  failed_.fetch_add(1);
  spdlog::error("recording {} not written: the server is stopping", name);
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
      if (queue_.empty()) return;  // stopping, and everything is written
      job = std::move(queue_.front());
      queue_.pop_front();
    }
    const std::string error = write_file_atomically(directory_, job.name, job.bytes);
    if (!error.empty()) {
      failed_.fetch_add(1);
      spdlog::error("recording not written: {}", error);
      continue;
    }
    written_.fetch_add(1);
    written_bytes_.fetch_add(job.bytes.size());
    spdlog::info("recording {} written ({} bytes)", (directory_ / job.name).string(),
                 job.bytes.size());
  }
}

}  // namespace ricochet::server
