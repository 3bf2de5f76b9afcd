#pragma once
/// Match records kept on local disk until the database has them, so that a result outlives the
/// database being away and the server being killed meanwhile.
///
/// Exactly once, in four steps:
///   1. journal first: every ended match with players gets a uuid and is kept here (keep:
///      written, fsync()ed, renamed into place, the directory fsync()ed) before its first
///      database attempt;
///   2. idempotent on the uuid: db::Matches::record_match finds a match already stored under it
///      and writes nothing, so any number of attempts of one record store it once;
///   3. removed after the commit (or after a refusal for good, logged and counted);
///   4. a crash or kill -9 between the commit and the remove leaves the file, and the next start
///      delivers it again (list): step 2 makes that a no-op. A crash before the commit delivers
///      it for the first time. Either way the match is in the database once.
///
/// In the outbox directory (created when missing, with `rejected/` in it):
///   `<uuid>.rec`       one kept record (results_outbox_format.h);
///   `<uuid>.rec.tmp`   a keep a crash cut short: never renamed, so never delivered (its match
///                      was not journalled, and had no database attempt either); removed by list;
///   `rejected/<name>`  a file that cannot be read back as a record (corrupt, truncated,
///                      oversized, misnamed), moved aside by list with the reason logged and
///                      counted, for an operator to look at. Never deleted, never a crash.
/// Thread-safe (the server keeps and removes on its DB thread, whose fsyncs stall no tick, and
/// lists at the start).
///
/// Shared: several processes (the servers of one Kubernetes volume) may use one directory. Each
/// delivers every record it lists, its own or another's (step 2 makes a record delivered by two
/// harmless); a record another process removed or rejected while this one listed is passed
/// over, not rejected; a `.tmp` is removed only when no live process holds its lock (keep()
/// holds an flock on it until the rename, and the kernel drops the lock of a killed process).
/// A live server also looks again now and then (list_left) for records another process left
/// there (one killed, or one whose database was away for long), so that they do not wait for
/// the next server to start.

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <mutex>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "results_outbox_format.h"

namespace ricochet::server {

class ResultsOutbox {
 public:
  /// Creates `directory` and its `rejected/` when missing; throws std::runtime_error naming the
  /// directory when it cannot.
  explicit ResultsOutbox(std::filesystem::path directory);

  /// Writes `<uuid>.rec` durably (the record must have a valid uuid); keeping it again rewrites
  /// it. False, with the reason logged, when the disk refused it: the record then lives in
  /// memory only.
  bool keep(const OutboxRecord& record);
  /// Removes `<uuid>.rec` (and syncs the directory). Logged when it fails.
  void remove(std::string_view uuid);
  /// Every kept record in the directory, oldest name first; files that are not one are moved to
  /// `rejected/` (logged, counted) and left `.tmp` files removed. Sets files() to the count.
  std::vector<OutboxRecord> list();
  /// As list(), but only the records this process does not hold whose file was last written
  /// `min_age_ms` or longer before `now_unix_ms` (Unix ms, passed in): a live writer delivers
  /// and removes its records within moments, so older ones were left (delivering one twice
  /// writes nothing, step 2). Adds them to those held.
  std::vector<OutboxRecord> list_left(std::int64_t now_unix_ms, std::int64_t min_age_ms);

  /// Records this process kept or listed and has not removed since (nor found removed, at a
  /// remove() or the next list()).
  std::uint64_t files() const;
  /// Files moved to rejected/ since the start.
  std::uint64_t rejected() const { return rejected_.load(); }
  const std::filesystem::path& directory() const { return directory_; }

 private:
  /// Moves `file` to rejected/ and logs why (unless another process took it first).
  void reject(const std::filesystem::path& file, const std::string& reason);
  /// list() and list_left(): the records in the directory that `wanted` (uuid, file) takes.
  std::vector<OutboxRecord> scan(
      const std::function<bool(std::string_view, const std::filesystem::path&)>& wanted);
  /// Removes the crash leftover `temp` unless a live keep() holds its lock.
  static void remove_leftover(const std::filesystem::path& temp);

  std::filesystem::path directory_;
  mutable std::mutex mutex_;
  std::set<std::string, std::less<>> held_;  ///< the uuids files() counts; under mutex_
  std::atomic<std::uint64_t> rejected_{0};
};

}  // namespace ricochet::server
