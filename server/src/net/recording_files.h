#pragma once
/// Match recordings onto disk as the matches run, on a thread of their own: a match strand hands
/// over each completed chunk (RecordingWriter::take_completed) and never waits for the disk.
///
/// In the recordings directory (created when missing), a match's file is
///   `match-<id>-<started unix ms>.rcr.part`  while the match runs: the magic and header chunk
///       once the first player joined, then every tick chunk as it completes, each write()n and
///       fsync()ed as it arrives (a chunk is the unit a cut file reads back to, and at most a few
///       a second arrive server-wide: one per 16 KiB of recording);
///   `match-<id>-<ended unix ms>.rcr`  once it ended: the last chunk and the footer appended,
///       the file fsync()ed, renamed in one step and the directory fsync()ed;
///   `match-<id>-<started unix ms>.interrupted.rcr`  a `.part` a crash left behind, renamed so at
///       the next start (logged once each, never deleted); it reads to its last whole chunk.
/// A write that fails (a full disk) stops that match's file where it is: it is renamed to its
/// interrupted name when the match ends, and the failure is logged and counted; the server runs
/// on. When the disk falls behind, has_room() turns false and the matches keep their chunks in
/// their writers, which stop at max_recording_bytes and mark the recording truncated as before.

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace ricochet::server {

class RecordingFiles {
 public:
  /// Renames every `.rcr.part` left in `directory` to its interrupted name (logging each), then
  /// starts the thread. `max_queued_bytes`: has_room() is false while more than that waits.
  RecordingFiles(std::filesystem::path directory, std::size_t max_queued_bytes);
  /// stop().
  ~RecordingFiles();
  RecordingFiles(const RecordingFiles&) = delete;
  RecordingFiles& operator=(const RecordingFiles&) = delete;

  /// "match-<match_id>-<started_unix_ms>.rcr.part".
  static std::string part_name(std::uint32_t match_id, std::int64_t started_unix_ms);
  /// "match-<match_id>-<ended_unix_ms>.rcr".
  static std::string file_name(std::uint32_t match_id, std::int64_t ended_unix_ms);
  /// "x.rcr.part" -> "x.interrupted.rcr".
  static std::string interrupted_name(const std::string& part_name);

  /// Thread-safe: whether the bytes waiting for the disk are within max_queued_bytes (a hand-off
  /// after a true may go over it by that one hand-off).
  bool has_room() const;
  /// Thread-safe: queues bytes to append to `part_name` (opened on its first bytes).
  void append(const std::string& part_name, std::vector<std::uint8_t> bytes);
  /// Thread-safe: queues the last bytes of `part_name`, after which the file is made durable
  /// and renamed to `final_name`. After stop() it is refused (logged, counted failed), and the
  /// `.part` stays for the next start.
  void finish(const std::string& part_name, const std::string& final_name,
              std::vector<std::uint8_t> bytes);
  /// Writes everything queued, then ends the thread; files of matches that did not finish stay
  /// `.part` (synced). Idempotent.
  void stop();

  const std::filesystem::path& directory() const { return directory_; }
  std::uint64_t written() const { return written_.load(); }  ///< finished files
  std::uint64_t written_bytes() const { return written_bytes_.load(); }
  std::uint64_t failed() const { return failed_.load(); }  ///< files that could not be finished
  std::uint64_t interrupted() const { return interrupted_.load(); }  ///< found at start

 private:
  struct Job {
    std::string part_name;
    std::string final_name;  ///< empty: an append
    std::vector<std::uint8_t> bytes;
  };
  struct Stream {
    int fd = -1;
    std::uint64_t bytes = 0;
    bool failed = false;  ///< a write failed: the file stays as it is
  };
  void keep_interrupted();
  void run();
  void write(const Job& job);
  /// Opens the stream's file when it is not open yet; false (logged) when it cannot.
  bool open(const std::string& name, Stream& stream);
  void fail(const std::string& name, Stream& stream, const std::string& what);

  const std::filesystem::path directory_;
  const std::size_t max_queued_bytes_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Job> queue_;
  bool stopping_ = false;
  std::atomic<std::size_t> queued_bytes_{0};
  std::map<std::string, Stream> streams_;  ///< the writer thread's only, by part name
  std::atomic<std::uint64_t> written_{0};
  std::atomic<std::uint64_t> written_bytes_{0};
  std::atomic<std::uint64_t> failed_{0};
  std::atomic<std::uint64_t> interrupted_{0};
  std::thread thread_;  ///< last: starts once everything above exists
};

}  // namespace ricochet::server
