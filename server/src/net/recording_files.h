#pragma once
/// Match recordings onto disk, on a thread of their own: a match strand hands the bytes over
/// and never waits for the disk. Each file is `match-<id>-<unix ms>.rcr` in the recordings
/// directory (created when missing), written to a temporary file and renamed into place, so a
/// crash leaves either the whole recording or none. A failed write is logged and counted; it
/// never stops the server.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <mutex>
#include <span>
#include <string>
#include <thread>
#include <vector>

namespace ricochet::server {

/// Writes `bytes` to `directory / name` through `.name.tmp` and a rename, creating the
/// directory. The error (naming the path and what the system said), or empty.
std::string write_file_atomically(const std::filesystem::path& directory, const std::string& name,
                                  std::span<const std::uint8_t> bytes);

class RecordingFiles {
 public:
  explicit RecordingFiles(std::filesystem::path directory);
  /// stop().
  ~RecordingFiles();
  RecordingFiles(const RecordingFiles&) = delete;
  RecordingFiles& operator=(const RecordingFiles&) = delete;

  /// "match-<match_id>-<ended_unix_ms>.rcr".
  static std::string file_name(std::uint32_t match_id, std::int64_t ended_unix_ms);

  /// Thread-safe: queues one recording. After stop() it is refused (logged, counted failed).
  void write(std::uint32_t match_id, std::int64_t ended_unix_ms, std::vector<std::uint8_t> bytes);
  /// Writes everything queued, then ends the thread. Idempotent.
  void stop();

  const std::filesystem::path& directory() const { return directory_; }
  std::uint64_t written() const { return written_.load(); }
  std::uint64_t written_bytes() const { return written_bytes_.load(); }
  std::uint64_t failed() const { return failed_.load(); }

 private:
  struct Job {
    std::string name;
    std::vector<std::uint8_t> bytes;
  };
  void run();

  const std::filesystem::path directory_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Job> queue_;
  bool stopping_ = false;
  std::atomic<std::uint64_t> written_{0};
  std::atomic<std::uint64_t> written_bytes_{0};
  std::atomic<std::uint64_t> failed_{0};
  std::thread thread_;  ///< last: starts once everything above exists
};

}  // namespace ricochet::server
