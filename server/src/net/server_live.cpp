// The live view's routes on the admin port (issue 32, "A match, live"): a match's map as JSON
// (web/map_view.h, made once per map at the start) and its live frames as server-sent events
// (web/frame_json.h). The match only swaps a frame pointer while watched (live_frame.h); the
// frames are encoded here, on an io_ thread, never on a match's strand.
#include <chrono>

#include "admin_http.h"
#include "frame_json.h"
#include "match_id.h"
#include "match_registry.h"
#include "server.h"
#include "steady_time.h"

namespace ricochet::server {

struct Server::LiveViewer {
  web::FrameStream frames;  ///< holds the viewer's seat on the match's feed
  std::shared_ptr<AdminEventStream> stream;
};

const char* name(LiveRefusal refusal) {
  switch (refusal) {
    case LiveRefusal::BadId:
      return "bad_id";
    case LiveRefusal::UnknownMatch:
      return "unknown_match";
    case LiveRefusal::UnknownPath:
      return "unknown_path";
    case LiveRefusal::TooManyViewers:
      return "too_many_viewers";
  }
  return "unknown";
}

namespace {

constexpr std::string_view kMatchesPrefix = "/api/matches/";

/// A path under kMatchesPrefix split at its first '/' after the prefix: "7/live" is {"7",
/// "live"}.
struct LivePath {
  std::string_view id;
  std::string_view what;
};

LivePath split_live_path(std::string_view path) {
  path.remove_prefix(kMatchesPrefix.size());
  const std::size_t slash = path.find('/');
  if (slash == std::string_view::npos) return {path, {}};
  return {path.substr(0, slash), path.substr(slash + 1)};
}

}  // namespace

void Server::refuse_live(LiveRefusal refusal, std::string_view detail) {
  live_refusals_[static_cast<std::size_t>(refusal)].fetch_add(1, std::memory_order_relaxed);
  episodes_.refuse(name(refusal), "dashboard live view", detail, steady_now_us());
}

std::variant<std::shared_ptr<MatchHost>, AdminReply> Server::live_match(std::string_view id_text) {
  const auto parsed = web::parse_match_id(id_text);
  if (const auto* why = std::get_if<std::string>(&parsed)) {
    refuse_live(LiveRefusal::BadId, *why);
    return AdminReply{404, *why + "\n"};
  }
  const std::uint32_t id = std::get<std::uint32_t>(parsed);
  for (auto& host : matches_->hosts()) {
    if (host->id() == id) return host;
  }
  std::string why = "no match " + std::to_string(id) + " here";
  refuse_live(LiveRefusal::UnknownMatch, why);
  return AdminReply{404, why + "\n"};
}

void Server::register_live() {
  AdminRoute route;
  route.path = std::string(kMatchesPrefix);
  route.prefix = true;
  route.before_stream = [this](const AdminRequest& request) -> std::optional<AdminReply> {
    const LivePath path = split_live_path(request.path);
    auto match = live_match(path.id);
    if (auto* refused = std::get_if<AdminReply>(&match)) return std::move(*refused);
    const auto& host = std::get<std::shared_ptr<MatchHost>>(match);
    if (path.what == "map") {
      const auto view = map_views_.find(host->map_name());
      if (view == map_views_.end()) return AdminReply{404, "no such map\n"};  // not in the rotation
      return AdminReply{200, view->second, "application/json"};
    }
    if (path.what != "live") {
      refuse_live(LiveRefusal::UnknownPath, "neither map nor live");
      return AdminReply{404, "a match has /map and /live\n"};
    }
    const int viewers = host->live_feed(config_.dashboard.live_feed())->viewers();
    if (viewers >= config_.dashboard.live_feed_max_viewers) {
      const std::string why =
          "match " + std::to_string(host->id()) + " has " + std::to_string(viewers) + " viewers";
      refuse_live(LiveRefusal::TooManyViewers, why);
      return AdminReply{503, "too many viewers: " + why + ", the most it takes\n"};
    }
    return std::nullopt;
  };
  route.stream = [this](const AdminRequest& request, std::shared_ptr<AdminEventStream> stream) {
    auto match = live_match(split_live_path(request.path).id);
    auto* host = std::get_if<std::shared_ptr<MatchHost>>(&match);
    std::optional<LiveFeed::Viewer> viewer;
    if (host) viewer = (*host)->live_feed(config_.dashboard.live_feed())->watch();
    if (!viewer) {  // it ended, or the last seat went to another, since before_stream
      if (host) refuse_live(LiveRefusal::TooManyViewers, "a seat taken meanwhile");
      stream->push(R"({"refused":")" + std::string(host ? "too_many_viewers" : "match_ended") +
                   R"("})");
      stream->close();
      return;
    }
    const std::lock_guard lock(live_mutex_);
    live_viewers_.push_back(std::make_shared<LiveViewer>(
        LiveViewer{web::FrameStream(std::move(*viewer)), std::move(stream)}));
  };
  admin_->add_route(std::move(route));
}

void Server::poll_live() {
  {
    const std::lock_guard lock(live_mutex_);
    std::erase_if(live_viewers_, [](const std::shared_ptr<LiveViewer>& viewer) {
      if (viewer->stream->closed()) return true;
      std::optional<std::string> json = viewer->frames.next();
      return json && !viewer->stream->push(std::move(*json));
    });
  }
  // Twice the feed's rate, so that a frame waits half an interval at most before it goes.
  const auto interval =
      std::chrono::microseconds(proto::kMicrosPerSecond / (2 * config_.dashboard.live_feed_hz));
  live_timer_.expires_after(interval);
  live_timer_.async_wait([this](const boost::system::error_code& error) {
    if (error || stopping_) return;  // cancelled, or stopping
    poll_live();
  });
}

}  // namespace ricochet::server
