#include "results_outbox.h"

#include <fcntl.h>
#include <spdlog/spdlog.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <system_error>

#include "durable_files.h"
#include "ricochet/db/matches.h"

namespace ricochet::server {

namespace {

namespace fs = std::filesystem;

constexpr std::string_view kSuffix = ".rec";
constexpr std::string_view kTempSuffix = ".rec.tmp";
constexpr const char* kRejected = "rejected";

bool ends_with(std::string_view name, std::string_view suffix) {
  return name.size() >= suffix.size() && name.substr(name.size() - suffix.size()) == suffix;
}

/// Whether `path` is gone (another process removed or moved it), not merely unreadable.
bool vanished(const fs::path& path) {
  std::error_code error;
  return fs::symlink_status(path, error).type() == fs::file_type::not_found;
}

/// The file's bytes, or why it cannot be read; at most kMaxOutboxFileBytes + 1 are read.
std::string read_file(const fs::path& path, std::vector<std::uint8_t>& bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "cannot open it";
  bytes.resize(kMaxOutboxFileBytes + 1);
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (in.bad()) return "cannot read it";
  bytes.resize(static_cast<std::size_t>(in.gcount()));
  return {};
}

}  // namespace

ResultsOutbox::ResultsOutbox(fs::path directory) : directory_(std::move(directory)) {
  std::error_code error;
  fs::create_directories(directory_ / kRejected, error);
  if (error)
    throw std::runtime_error("cannot create the results outbox " + directory_.string() + ": " +
                             error.message());
}

bool ResultsOutbox::keep(const OutboxRecord& record) {
  const std::string& uuid = record.record.uuid;
  const fs::path temp = directory_ / (uuid + std::string(kTempSuffix));
  const fs::path target = directory_ / (uuid + std::string(kSuffix));
  const auto failed = [&](const std::string& why) {
    spdlog::error(
        "results outbox: match {} ({}) cannot be kept on disk: {}; it is kept in memory only",
        record.match_id, uuid, why);
    std::error_code ignored;
    fs::remove(temp, ignored);
    return false;
  };
  // Locked until it is renamed (the lock goes with the close): another process's list() leaves
  // a locked .tmp alone. Should that list() have unlinked the file between the open and the
  // lock, the file is made again.
  int fd = -1;
  for (int attempt = 0; attempt < 2 && fd < 0; ++attempt) {
    fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0600);
    if (fd < 0) return failed("cannot create " + temp.string() + ": " + errno_text());
    struct stat linked {};
    if (::flock(fd, LOCK_EX) != 0 || ::fstat(fd, &linked) != 0 || linked.st_nlink == 0) {
      ::close(fd);
      fd = -1;
    }
  }
  if (fd < 0) return failed("cannot lock " + temp.string() + ": " + errno_text());
  std::string error = write_all(fd, encode_outbox_record(record));
  if (error.empty() && ::fsync(fd) != 0) error = "fsync failed: " + errno_text();
  if (!error.empty()) {
    ::close(fd);
    return failed(error);
  }
  std::error_code renamed;
  fs::rename(temp, target, renamed);
  ::close(fd);
  if (renamed) return failed("cannot rename it to " + target.string() + ": " + renamed.message());
  if (std::string synced = sync_directory(directory_); !synced.empty()) return failed(synced);
  const std::lock_guard lock(mutex_);
  held_.insert(uuid);
  return true;
}

std::uint64_t ResultsOutbox::files() const {
  const std::lock_guard lock(mutex_);
  return held_.size();
}

void ResultsOutbox::remove(std::string_view uuid) {
  const fs::path file = directory_ / (std::string(uuid) + std::string(kSuffix));
  std::error_code error;
  const bool removed = fs::remove(file, error);
  if (error) {
    spdlog::error("results outbox: cannot remove {}: {}", file.string(), error.message());
    return;
  }
  {
    const std::lock_guard lock(mutex_);
    const auto held = held_.find(uuid);
    if (held != held_.end()) held_.erase(held);  // removed here, or by another process
  }
  if (!removed) return;
  // Not synced, the removal may be undone by a power loss: the next start delivers the record
  // again, which writes nothing (results_outbox.h).
  if (std::string synced = sync_directory(directory_); !synced.empty())
    spdlog::warn("results outbox: {}", synced);
}

void ResultsOutbox::reject(const fs::path& file, const std::string& reason) {
  const fs::path target = directory_ / kRejected / file.filename();
  std::error_code error;
  fs::rename(file, target, error);
  if (error && vanished(file)) return;  // another process delivered or moved it meanwhile
  rejected_.fetch_add(1);
  if (error) {
    spdlog::error("results outbox: {} is not a match record ({}) and cannot be moved to {}: {}",
                  file.string(), reason, target.string(), error.message());
    return;
  }
  spdlog::error("results outbox: {} is not a match record ({}); moved to {}", file.string(), reason,
                target.string());
}

void ResultsOutbox::remove_leftover(const fs::path& temp) {
  const int fd = ::open(temp.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return;  // gone: renamed or removed by its writer or another list()
  struct stat held {};
  struct stat named {};
  // Unlinked only while locked here, and only the file locked (not one made since).
  if (::flock(fd, LOCK_EX | LOCK_NB) == 0 && ::fstat(fd, &held) == 0 &&
      ::stat(temp.c_str(), &named) == 0 && held.st_ino == named.st_ino &&
      held.st_dev == named.st_dev && ::unlink(temp.c_str()) == 0) {
    spdlog::info("results outbox: {} was cut short by a crash before it was kept; removed",
                 temp.filename().string());
  }
  ::close(fd);
}

std::vector<OutboxRecord> ResultsOutbox::list() {
  return scan([](std::string_view, const fs::path&) { return true; });
}

std::vector<OutboxRecord> ResultsOutbox::list_left(std::int64_t now_unix_ms,
                                                   std::int64_t min_age_ms) {
  return scan([&](std::string_view uuid, const fs::path& path) {
    {
      const std::lock_guard lock(mutex_);
      if (held_.contains(uuid)) return false;  // this process delivers it
    }
    struct stat file {};
    if (::stat(path.c_str(), &file) != 0) return false;  // gone meanwhile
    const std::int64_t written_ms =
        static_cast<std::int64_t>(file.st_mtim.tv_sec) * 1000 + file.st_mtim.tv_nsec / 1'000'000;
    return now_unix_ms - written_ms >= min_age_ms;
  });
}

std::vector<OutboxRecord> ResultsOutbox::scan(
    const std::function<bool(std::string_view, const fs::path&)>& wanted) {
  std::vector<fs::path> names;
  std::error_code error;
  for (fs::directory_iterator it(directory_, error), end; !error && it != end;
       it.increment(error)) {
    if (it->is_directory(error) && it->path().filename() == kRejected) continue;
    names.push_back(it->path());
  }
  if (error)
    spdlog::error("results outbox: cannot list {}: {}", directory_.string(), error.message());
  std::sort(names.begin(), names.end());
  std::vector<OutboxRecord> kept;
  for (const fs::path& path : names) {
    const std::string name = path.filename().string();
    if (ends_with(name, kTempSuffix)) {
      remove_leftover(path);
      continue;
    }
    const std::string uuid = name.substr(0, name.size() - std::min(name.size(), kSuffix.size()));
    if (!ends_with(name, kSuffix) || !db::is_match_uuid(uuid)) {
      reject(path, "its name is not <uuid>.rec");
      continue;
    }
    if (vanished(path)) continue;  // delivered by another process since the directory was read
    if (!wanted(uuid, path)) continue;
    std::error_code size_error;
    if (!fs::is_regular_file(path, size_error)) {
      reject(path, "not a regular file");
      continue;
    }
    const std::uintmax_t size = fs::file_size(path, size_error);
    if (size_error || size > kMaxOutboxFileBytes) {
      reject(path, size_error ? size_error.message()
                              : "oversized: " + std::to_string(size) + " bytes, at most " +
                                    std::to_string(kMaxOutboxFileBytes));
      continue;
    }
    std::vector<std::uint8_t> bytes;
    if (std::string unreadable = read_file(path, bytes); !unreadable.empty()) {
      if (!vanished(path)) reject(path, unreadable);
      continue;
    }
    DecodedOutbox decoded = decode_outbox_record(bytes);
    if (!decoded.ok) {
      reject(path, decoded.problem);
      continue;
    }
    if (decoded.record.record.uuid != uuid) {
      reject(path, "it holds match " + decoded.record.record.uuid);
      continue;
    }
    kept.push_back(std::move(decoded.record));
  }
  const std::lock_guard lock(mutex_);
  // Those another process delivered meanwhile are no longer held here.
  std::erase_if(held_, [this](const std::string& uuid) {
    return vanished(directory_ / (uuid + std::string(kSuffix)));
  });
  for (const OutboxRecord& record : kept) held_.insert(record.record.uuid);
  return kept;
}

}  // namespace ricochet::server
