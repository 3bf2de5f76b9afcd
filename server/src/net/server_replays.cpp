// The dashboard's Recordings page on the admin port: the recordings directory listed
// (recording_catalog.h), replays started, watched and cancelled on the server's own pool
// (replay_jobs.h, never a match's strand), their frames read by tick range (replay_frames.h)
// and the top-down view of a recording's map (map_view.h). Every id and query number from the
// URL is untrusted: checked before use, refused with 400 or 404 and counted.
//
//   GET  /api/recordings                        the list
//   GET  /api/recordings/<id>                   {"id","job":{...}|null,"summary":{...}|null}
//   GET  /api/recordings/<id>/frames?from=T0&to=T1   ticks [T0, T1) of a finished replay
//   GET  /api/recordings/<id>/map               the recording's map, when the server has it
//   POST /api/recordings/<id>/replay            starts (or reuses) its replay; busy: 503
//   POST /api/recordings/<id>/cancel            stops it; 404 when none queued or running
#include <charconv>
#include <chrono>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "admin_http.h"
#include "recording_catalog.h"
#include "replay_jobs.h"
#include "server.h"
#include "steady_time.h"

namespace ricochet::server {

namespace {

constexpr std::string_view kRecordingsPrefix = "/api/recordings/";

AdminReply json_reply(std::string body) {
  return {200, std::move(body), "application/json"};
}

/// The value of `key` in an undecoded query ("from=1&to=60") when it is 1..10 decimal digits
/// that fit 32 bits; nothing otherwise (missing, empty, a sign, other characters).
std::optional<std::uint32_t> query_number(std::string_view query, std::string_view key) {
  while (!query.empty()) {
    const auto amp = query.find('&');
    const std::string_view pair = query.substr(0, amp);
    query = amp == std::string_view::npos ? std::string_view{} : query.substr(amp + 1);
    if (!pair.starts_with(key) || pair.size() <= key.size() || pair[key.size()] != '=') continue;
    const std::string_view text = pair.substr(key.size() + 1);
    std::uint32_t value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || text.size() > 10 || error != std::errc{} ||
        end != text.data() + text.size()) {
      return std::nullopt;
    }
    return value;
  }
  return std::nullopt;
}

std::variant<std::vector<std::uint8_t>, std::string> read_whole(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::string("cannot open the recording");
  std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                  std::istreambuf_iterator<char>());
  if (in.bad()) return std::string("cannot read the recording");
  return bytes;
}

}  // namespace

void Server::start_replays() {
  recording_catalog_ = std::make_unique<RecordingCatalog>(config_.recordings_path());
  const ReplayJobsConfig jobs{.workers = config_.dashboard.replay_workers,
                              .max_replays = config_.dashboard.max_replays,
                              .memory_mb = config_.dashboard.replay_memory_mb};
  replays_ = std::make_unique<ReplayJobs>(
      jobs,
      [catalog = recording_catalog_.get()](
          const std::string& id) -> std::variant<std::vector<std::uint8_t>, std::string> {
        std::string error;
        const auto file = catalog->file_of(id, error);
        if (!file) return error.empty() ? std::string("no such recording") : error;
        return read_whole(*file);
      },
      [] { return static_cast<double>(steady_now_us()) / 1e6; });
}

void Server::register_replays() {
  AdminRoute list;
  list.path = "/api/recordings";
  list.handler = [this](const AdminRequest&, AdminAnswer answer) {
    answer(json_reply(recording_list_json(recording_catalog_->list())));
  };
  admin_->add_route(std::move(list));
  AdminRoute read;
  read.path = std::string(kRecordingsPrefix);
  read.prefix = true;
  read.handler = [this](const AdminRequest& request, AdminAnswer answer) {
    answer(recording_get(request));
  };
  admin_->add_route(std::move(read));
  AdminRoute act;
  act.path = std::string(kRecordingsPrefix);
  act.prefix = true;
  act.method = "POST";
  act.handler = [this](const AdminRequest& request, AdminAnswer answer) {
    answer(recording_post(request));
  };
  admin_->add_route(std::move(act));
}

std::optional<AdminReply> Server::recording_of(std::string_view rest, std::string& id,
                                               std::string& action) {
  const auto slash = rest.find('/');
  id = std::string(rest.substr(0, slash));
  action = slash == std::string_view::npos ? std::string{} : std::string(rest.substr(slash + 1));
  std::string error;
  if (recording_catalog_->file_of(id, error)) return std::nullopt;
  if (!check_recording_id(id).empty()) return AdminReply{400, "bad recording id: " + error + "\n"};
  replay_requests_refused_.fetch_add(1, std::memory_order_relaxed);
  return AdminReply{404, error + "\n"};
}

AdminReply Server::recording_get(const AdminRequest& request) {
  std::string id, action;
  if (auto refused = recording_of(request.path.substr(kRecordingsPrefix.size()), id, action)) {
    return *std::move(refused);
  }
  if (action.empty()) {
    const auto status = replays_->status(id);
    std::string json = "{\"id\":\"" + id + "\",\"job\":";
    json += status ? replay_job_json(*status) : "null";
    const auto frames =
        status && status->state == ReplayJobState::Done ? replays_->result(id) : nullptr;
    json += ",\"summary\":";
    json += frames ? replay_summary_json(*frames) : "null";
    return json_reply(json + "}");
  }
  if (action == "frames") {
    const auto from = query_number(request.query, "from");
    const auto to = query_number(request.query, "to");
    if (!from || !to) {
      replay_requests_refused_.fetch_add(1, std::memory_order_relaxed);
      return {400, "frames need from=T0&to=T1, ticks as decimal numbers\n"};
    }
    const auto frames = replays_->result(id);
    if (!frames) return {409, "not replayed yet: POST .../replay and wait for done\n"};
    std::string error;
    std::string json = frames_json(*frames, *from, *to, error);
    if (!error.empty()) {
      replay_requests_refused_.fetch_add(1, std::memory_order_relaxed);
      return {400, error + "\n"};
    }
    return json_reply(std::move(json));
  }
  if (action == "map") {
    std::string error;
    const auto file = recording_catalog_->file_of(id, error);
    if (!file) return {404, "no such recording\n"};
    const RecordingEntry entry = describe_recording(*file, id);
    const auto view = map_views_.find(entry.map);
    if (!entry.unreadable.empty() || view == map_views_.end()) {
      return {404, "this server has not the recording's map\n"};
    }
    return json_reply(view->second);
  }
  replay_requests_refused_.fetch_add(1, std::memory_order_relaxed);
  return {404, "unknown recording path\n"};
}

AdminReply Server::recording_post(const AdminRequest& request) {
  std::string id, action;
  if (auto refused = recording_of(request.path.substr(kRecordingsPrefix.size()), id, action)) {
    return *std::move(refused);
  }
  if (action == "replay") {
    std::string busy;
    const auto status = replays_->start(id, busy);
    if (!status) return {503, busy + "\n"};
    return json_reply(replay_job_json(*status));
  }
  if (action == "cancel") {
    if (!replays_->cancel(id)) return {404, "no replay of it is queued or running\n"};
    return json_reply("{\"cancelled\":true}");
  }
  replay_requests_refused_.fetch_add(1, std::memory_order_relaxed);
  return {404, "unknown recording action\n"};
}

void Server::report_replays(MetricsSink& sink) const {
  sink.counter("ricochet_recordings_unreadable_total",
               "Distinct files of the recordings directory that are not readable recordings", {},
               static_cast<double>(recording_catalog_->unreadable_files()));
  sink.counter("ricochet_replay_requests_refused_total",
               "Dashboard replay requests refused: a bad recording id, path or tick range",
               {{"reason", "bad_id"}}, static_cast<double>(recording_catalog_->bad_ids()));
  sink.counter("ricochet_replay_requests_refused_total",
               "Dashboard replay requests refused: a bad recording id, path or tick range",
               {{"reason", "bad_request"}},
               static_cast<double>(replay_requests_refused_.load(std::memory_order_relaxed)));
  sink.counter("ricochet_replays_refused_busy_total",
               "Replays refused: dashboard.max_replays queued or running already", {},
               static_cast<double>(replays_->refused_busy()));
  sink.counter("ricochet_replays_evicted_total",
               "Finished replays dropped from the cache, least recently used first", {},
               static_cast<double>(replays_->evicted()));
  sink.gauge("ricochet_replay_cache_bytes", "Bytes of the finished replays' frames kept", {},
             static_cast<double>(replays_->cached_bytes()));
}

}  // namespace ricochet::server
