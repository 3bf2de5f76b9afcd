/// The recordings directory, listed from each file's header and footer (recording_catalog.h).

#include "recording_catalog.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <charconv>
#include <fstream>
#include <system_error>
#include <variant>

#include "ricochet/server/map.h"
#include "ricochet/server/match_config.h"
#include "ricochet/server/recording.h"
#include "ricochet/tools/json_text.h"

namespace ricochet::server {

namespace {

constexpr std::string_view kPrefix = "match-";
constexpr std::string_view kInterrupted = ".interrupted";
constexpr std::string_view kSuffix = ".rcr";
constexpr std::size_t kMaxIdBytes = 64;

/// The two numbers of "match-<id>-<unix ms>[.interrupted]"; false when `id` is not that.
bool parse_id(std::string_view id, std::uint32_t& match_id, std::int64_t& unix_ms,
              bool& interrupted) {
  if (id.size() > kMaxIdBytes || !id.starts_with(kPrefix)) return false;
  id.remove_prefix(kPrefix.size());
  interrupted = id.ends_with(kInterrupted);
  if (interrupted) id.remove_suffix(kInterrupted.size());
  const auto dash = id.find('-');
  if (dash == std::string_view::npos) return false;
  const auto number = [](std::string_view digits, auto& value) {
    if (digits.empty() || digits.size() > 19 ||
        !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) {
      return false;
    }
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    return error == std::errc{} && end == digits.data() + digits.size();
  };
  return number(id.substr(0, dash), match_id) && number(id.substr(dash + 1), unix_ms);
}

/// Up to `count` bytes from `offset`; fewer when the file is shorter. False when it cannot be read.
bool read_at(std::ifstream& in, std::uint64_t offset, std::size_t count,
             std::vector<std::uint8_t>& bytes) {
  bytes.resize(count);
  in.clear();
  in.seekg(static_cast<std::streamoff>(offset));
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(count));
  if (in.bad()) return false;
  bytes.resize(static_cast<std::size_t>(in.gcount()));
  return true;
}

}  // namespace

std::string check_recording_id(std::string_view id) {
  std::uint32_t match_id = 0;
  std::int64_t unix_ms = 0;
  bool interrupted = false;
  if (parse_id(id, match_id, unix_ms, interrupted)) return {};
  return "a recording id is match-<match id>-<unix ms>[.interrupted] (at most " +
         std::to_string(kMaxIdBytes) + " bytes), got " +
         tools::json_string(id.substr(0, kMaxIdBytes));
}

RecordingEntry describe_recording(const std::filesystem::path& file, const std::string& id) {
  RecordingEntry entry;
  entry.id = id;
  parse_id(id, entry.match_id, entry.unix_ms, entry.interrupted);
  std::error_code error;
  entry.size_bytes = std::filesystem::file_size(file, error);
  const auto unreadable = [&](std::string why) {
    entry.unreadable = std::move(why);
    return entry;
  };
  if (error) return unreadable("cannot read its size: " + error.message());
  if (entry.size_bytes > kMaxRecordingBytes) {
    return unreadable("a recording is at most " + std::to_string(kMaxRecordingBytes) +
                      " bytes, got " + std::to_string(entry.size_bytes));
  }
  std::ifstream in(file, std::ios::binary);
  std::vector<std::uint8_t> bytes;
  if (!in || !read_at(in, 0, 14, bytes)) return unreadable("cannot open");
  auto header_size = recording_header_bytes(bytes);
  if (const auto* bad = std::get_if<RecordingError>(&header_size)) return unreadable(bad->message);
  if (!read_at(in, 0, std::get<std::size_t>(header_size), bytes)) return unreadable("read failed");
  auto header = read_recording_header(bytes);
  if (const auto* bad = std::get_if<RecordingError>(&header)) return unreadable(bad->message);
  const RecordingHeader& head = std::get<RecordingHeader>(header);
  if (head.map_files.empty()) return unreadable("its header names no map file");
  std::vector<MapFile> files;
  for (const RecordedFile& each : head.map_files) files.push_back({each.path, each.text});
  const MapResult map = parse_map_files(files);
  if (const auto* bad = std::get_if<MapError>(&map))
    return unreadable("its map: " + bad->describe());
  const auto config = decode_match_config(head.config);
  if (const auto* bad = std::get_if<std::string>(&config)) return unreadable("its config: " + *bad);
  entry.map = std::get<Map>(map).name;
  entry.mode = name(std::get<MatchConfig>(config).rules.mode);
  entry.tick_rate_hz = head.tick_rate_hz;

  const std::uint64_t header_end = std::get<std::size_t>(header_size);
  const std::uint64_t tail =
      std::min<std::uint64_t>(kMaxRecordingFooterBytes, entry.size_bytes - header_end);
  if (!read_at(in, entry.size_bytes - tail, tail, bytes)) return unreadable("read failed");
  if (const auto footer = read_recording_footer(bytes)) {
    entry.complete = true;
    entry.truncated = footer->truncated;
    entry.ticks = footer->last_tick;
    entry.seconds = static_cast<double>(footer->last_tick) / head.tick_rate_hz;
    entry.players = footer->players;
  }
  return entry;
}

RecordingCatalog::RecordingCatalog(std::filesystem::path directory)
    : directory_(std::move(directory)) {}

RecordingList RecordingCatalog::list() {
  RecordingList list;
  std::error_code error;
  if (!std::filesystem::is_directory(directory_, error)) return list;
  std::filesystem::directory_iterator it(directory_, error);
  for (; !error && it != std::filesystem::directory_iterator(); it.increment(error)) {
    const std::string name = it->path().filename().string();
    std::error_code type_error;
    // Symbolic links are not followed out of the directory: only files the server wrote.
    const bool file = it->symlink_status(type_error).type() == std::filesystem::file_type::regular;
    if (!name.ends_with(kSuffix) || !file) continue;
    const std::string id = name.substr(0, name.size() - kSuffix.size());
    RecordingEntry entry;
    if (check_recording_id(id).empty()) {
      entry = describe_recording(it->path(), id);
    } else {
      entry.id = id;  // listed so the operator sees it, never opened by id
      entry.size_bytes = it->file_size(type_error);
      entry.unreadable = "not a name the server writes (match-<match id>-<unix ms>.rcr)";
    }
    if (!entry.unreadable.empty()) {
      ++list.unreadable;
      const std::lock_guard lock(mutex_);
      if (reported_.insert(name + " " + std::to_string(entry.size_bytes)).second) {
        unreadable_files_.fetch_add(1);
        spdlog::warn("recording {} is not readable: {}", it->path().string(), entry.unreadable);
      }
    }
    list.entries.push_back(std::move(entry));
  }
  if (error) {
    spdlog::error("cannot list the recordings in {}: {}", directory_.string(), error.message());
  }
  std::sort(list.entries.begin(), list.entries.end(),
            [](const RecordingEntry& a, const RecordingEntry& b) {
              return a.unix_ms != b.unix_ms ? a.unix_ms > b.unix_ms : a.id < b.id;
            });
  return list;
}

std::optional<std::filesystem::path> RecordingCatalog::file_of(std::string_view id,
                                                               std::string& error) const {
  error = check_recording_id(id);
  if (!error.empty()) {
    bad_ids_.fetch_add(1);
    return std::nullopt;
  }
  std::filesystem::path file = directory_ / (std::string(id) + std::string(kSuffix));
  std::error_code status_error;
  if (!std::filesystem::is_regular_file(std::filesystem::symlink_status(file, status_error))) {
    error = "no recording " + std::string(id);
    return std::nullopt;
  }
  return file;
}

std::string recording_list_json(const RecordingList& list) {
  std::string out = "{\"recordings\":[";
  for (std::size_t i = 0; i < list.entries.size(); ++i) {
    const RecordingEntry& e = list.entries[i];
    if (i) out += ',';
    out += "{\"id\":" + tools::json_string(e.id);
    out += ",\"match_id\":" + std::to_string(e.match_id);
    out += ",\"unix_ms\":" + std::to_string(e.unix_ms);
    out += ",\"size_bytes\":" + std::to_string(e.size_bytes);
    out += ",\"interrupted\":";
    out += e.interrupted ? "true" : "false";
    if (!e.unreadable.empty()) {
      out += ",\"unreadable\":" + tools::json_string(e.unreadable) + "}";
      continue;
    }
    out += ",\"map\":" + tools::json_string(e.map);
    out += ",\"mode\":" + tools::json_string(e.mode);
    out += ",\"tick_rate_hz\":" + std::to_string(e.tick_rate_hz);
    out += ",\"complete\":";
    out += e.complete ? "true" : "false";
    out += ",\"truncated\":";
    out += e.truncated ? "true" : "false";
    out += ",\"ticks\":" + (e.ticks ? std::to_string(*e.ticks) : std::string("null"));
    char seconds[32] = "null";
    if (e.seconds) std::snprintf(seconds, sizeof seconds, "%.3f", *e.seconds);
    out += ",\"seconds\":";
    out += seconds;
    out += ",\"players\":" + (e.players ? std::to_string(*e.players) : std::string("null"));
    out += '}';
  }
  out += "],\"unreadable\":" + std::to_string(list.unreadable) + "}";
  return out;
}

}  // namespace ricochet::server
