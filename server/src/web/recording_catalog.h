#pragma once
/// The recordings directory as the dashboard's "Recordings" page lists it: one entry per file,
/// read from its header chunk and its footer only (the first and last bytes; the ticks are never
/// decoded, nothing is replayed), so listing a directory of large files stays cheap.
///
/// Everything in the directory is untrusted: a file that is not a readable recording is listed
/// as unreadable with the reason, logged once and counted, never a crash. So is an id a URL
/// names: only the names RecordingFiles writes are ids (check_recording_id), so no id reaches
/// outside the directory.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace ricochet::server {

/// A file name without ".rcr" is its id: "match-3-1764966123456" or
/// "match-3-1764966123456.interrupted". Empty when `id` is one; otherwise why not.
std::string check_recording_id(std::string_view id);

struct RecordingEntry {
  std::string id;                ///< check_recording_id() accepts it
  std::uint32_t match_id = 0;    ///< from the name
  std::int64_t unix_ms = 0;      ///< from the name: when it ended (interrupted: started), ms
  std::uint64_t size_bytes = 0;  ///< of the file
  bool interrupted = false;      ///< a ".interrupted.rcr": its server stopped mid-match
  /// Empty: the fields below are read; otherwise why the file is not a readable recording.
  std::string unreadable;
  std::string map;   ///< the map's name (its first file's stem)
  std::string mode;  ///< "ffa" or "tdm"
  std::uint32_t tick_rate_hz = 0;
  bool complete = false;   ///< it has its footer (a whole file)
  bool truncated = false;  ///< the footer says the writer reached its size limit
  /// The last tick, from the footer; unset for a file without one (cut short: replaying it
  /// tells how far it goes).
  std::optional<std::uint32_t> ticks;
  /// ticks / tick_rate_hz, s; unset with ticks.
  std::optional<double> seconds;
  /// Distinct accounts that joined, from the footer; unset without one or in a version 1 file
  /// (its footer does not count them).
  std::optional<std::uint32_t> players;
};

/// One listing: every `.rcr` file of the directory, newest first.
struct RecordingList {
  std::vector<RecordingEntry> entries;
  std::size_t unreadable = 0;  ///< entries with `unreadable` set
};

/// Reads one file's header and footer (at most kMaxRecordingHeaderBytes and the footer's bytes).
/// `id` must be the file's name without ".rcr" (check_recording_id).
RecordingEntry describe_recording(const std::filesystem::path& file, const std::string& id);

class RecordingCatalog {
 public:
  explicit RecordingCatalog(std::filesystem::path directory);

  /// Thread-safe. A missing directory lists nothing (no match recorded yet).
  RecordingList list();
  /// Thread-safe: the file of a checked id; empty when `id` is not one (why in `error`) or no
  /// such file is there.
  std::optional<std::filesystem::path> file_of(std::string_view id, std::string& error) const;

  const std::filesystem::path& directory() const { return directory_; }
  /// Distinct unreadable files seen by list() (each logged once, by name and size).
  std::uint64_t unreadable_files() const { return unreadable_files_.load(); }
  /// Ids refused by file_of().
  std::uint64_t bad_ids() const { return bad_ids_.load(); }

 private:
  const std::filesystem::path directory_;
  std::mutex mutex_;
  std::set<std::string> reported_;  ///< "name size" of the unreadable files logged
  std::atomic<std::uint64_t> unreadable_files_{0};
  mutable std::atomic<std::uint64_t> bad_ids_{0};
};

/// The listing as the page reads it: {"recordings":[{...}],"unreadable":N}.
std::string recording_list_json(const RecordingList& list);

}  // namespace ricochet::server
