/// The Recordings page's routes, requests to replies (replay_routes.h).

#include "replay_routes.h"

#include <charconv>
#include <fstream>
#include <iterator>
#include <utility>
#include <variant>
#include <vector>

#include "ricochet/tools/json_text.h"

namespace ricochet::server {

namespace {

RecordingsReply json_reply(std::string body) {
  return {200, std::move(body), "application/json"};
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

std::optional<std::uint32_t> query_tick(std::string_view query, std::string_view key) {
  std::optional<std::uint32_t> found;
  while (!query.empty()) {
    const auto amp = query.find('&');
    const std::string_view pair = query.substr(0, amp);
    query = amp == std::string_view::npos ? std::string_view{} : query.substr(amp + 1);
    if (!pair.starts_with(key) || pair.size() <= key.size() || pair[key.size()] != '=') continue;
    if (found) return std::nullopt;  // the key twice: which one was meant is unknown
    const std::string_view text = pair.substr(key.size() + 1);
    std::uint32_t value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || text.size() > 10 || error != std::errc{} ||
        end != text.data() + text.size()) {
      return std::nullopt;
    }
    found = value;
  }
  return found;
}

ReplayJobs::Source recording_source(const RecordingCatalog& catalog) {
  return [&catalog](const std::string& id) -> std::variant<std::vector<std::uint8_t>, std::string> {
    std::string error;
    const auto file = catalog.file_of(id, error);
    if (!file) return error.empty() ? std::string("no such recording") : error;
    return read_whole(*file);
  };
}

ReplayRoutes::ReplayRoutes(RecordingCatalog& catalog, ReplayJobs& jobs, const MapViews& map_views)
    : catalog_(catalog), jobs_(jobs), map_views_(map_views) {}

RecordingsReply ReplayRoutes::list() {
  return json_reply(recording_list_json(catalog_.list()));
}

RecordingsReply ReplayRoutes::refuse(unsigned status, std::string line) {
  bad_requests_.fetch_add(1, std::memory_order_relaxed);
  return {status, std::move(line) + "\n"};
}

RecordingsReply ReplayRoutes::answer(const RecordingsRequest& request) {
  if (!request.path.starts_with(kPrefix)) return refuse(404, "unknown recording path");
  // "<id>" or "<id>/<action>".
  const std::string_view rest = request.path.substr(kPrefix.size());
  const auto slash = rest.find('/');
  const std::string id(rest.substr(0, slash));
  const std::string_view action =
      slash == std::string_view::npos ? std::string_view{} : rest.substr(slash + 1);
  std::string error;
  if (!catalog_.file_of(id, error)) {
    // The catalog counts a bad id (bad_ids()); an unknown one is counted here.
    if (!check_recording_id(id).empty()) return {400, "bad recording id: " + error + "\n"};
    return refuse(404, error);
  }
  if (request.method == "GET") return get(id, action, request.query);
  if (request.method == "POST") return post(id, action);
  return refuse(405, "GET or POST only");
}

RecordingsReply ReplayRoutes::get(const std::string& id, std::string_view action,
                                  std::string_view query) {
  if (action.empty()) {
    const auto status = jobs_.status(id);
    std::string json = "{\"id\":" + tools::json_string(id) + ",\"job\":";
    json += status ? replay_job_json(*status) : "null";
    const auto frames =
        status && status->state == ReplayJobState::Done ? jobs_.result(id) : nullptr;
    json += ",\"summary\":";
    json += frames ? replay_summary_json(*frames) : "null";
    return json_reply(json + "}");
  }
  if (action == "frames") {
    const auto from = query_tick(query, "from");
    const auto to = query_tick(query, "to");
    if (!from || !to) return refuse(400, "frames need from=T0&to=T1, ticks as decimal numbers");
    const auto frames = jobs_.result(id);
    if (!frames) return {409, "not replayed yet: POST .../replay and wait for done\n"};
    std::string error;
    std::string json = frames_json(*frames, *from, *to, error);
    if (!error.empty()) return refuse(400, error);
    return json_reply(std::move(json));
  }
  if (action == "map") {
    std::string error;
    const auto file = catalog_.file_of(id, error);
    if (!file) return {404, "no such recording\n"};
    const RecordingEntry entry = describe_recording(*file, id);
    const auto view = map_views_.find(entry.map);
    if (!entry.unreadable.empty() || view == map_views_.end()) {
      return {404, "this server has not the recording's map\n"};
    }
    return json_reply(view->second);
  }
  return refuse(404, "unknown recording path");
}

RecordingsReply ReplayRoutes::post(const std::string& id, std::string_view action) {
  if (action == "replay") {
    std::string busy;
    const auto status = jobs_.start(id, busy);
    if (!status) return {503, busy + "\n"};
    return json_reply(replay_job_json(*status));
  }
  if (action == "cancel") {
    if (!jobs_.cancel(id)) return {404, "no replay of it is queued or running\n"};
    return json_reply("{\"cancelled\":true}");
  }
  return refuse(404, "unknown recording action");
}

}  // namespace ricochet::server
