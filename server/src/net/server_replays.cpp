// The dashboard's Recordings page on the admin port: the routes of replay_routes.h (which
// checks every id and query number and answers), over the server's recordings directory, its
// own replay pool (never a match's strand) and the map views made at the start.
#include <memory>
#include <string>
#include <utility>

#include "admin_http.h"
#include "recording_catalog.h"
#include "replay_jobs.h"
#include "replay_routes.h"
#include "server.h"
#include "steady_time.h"

namespace ricochet::server {

namespace {

AdminReply admin_reply(RecordingsReply reply) {
  return {reply.status, std::move(reply.body), std::move(reply.content_type)};
}

}  // namespace

void Server::start_replays() {
  recording_catalog_ = std::make_unique<RecordingCatalog>(config_.recordings_path());
  const ReplayJobsConfig jobs{.workers = config_.dashboard.replay_workers,
                              .max_replays = config_.dashboard.max_replays,
                              .memory_mb = config_.dashboard.replay_memory_mb};
  replays_ = std::make_unique<ReplayJobs>(jobs, recording_source(*recording_catalog_), [] {
    return static_cast<double>(steady_now_us()) / 1e6;
  });
  replay_routes_ = std::make_unique<ReplayRoutes>(*recording_catalog_, *replays_, map_views_);
}

void Server::register_replays() {
  AdminRoute list;
  list.path = std::string(ReplayRoutes::kListPath);
  list.handler = [this](const AdminRequest&, AdminAnswer answer) {
    answer(admin_reply(replay_routes_->list()));
  };
  admin_->add_route(std::move(list));
  for (const char* method : {"GET", "POST"}) {
    AdminRoute under;
    under.path = std::string(ReplayRoutes::kPrefix);
    under.prefix = true;
    under.method = method;
    under.handler = [this](const AdminRequest& request, AdminAnswer answer) {
      answer(admin_reply(replay_routes_->answer({request.method, request.path, request.query})));
    };
    admin_->add_route(std::move(under));
  }
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
               {{"reason", "bad_request"}}, static_cast<double>(replay_routes_->bad_requests()));
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
