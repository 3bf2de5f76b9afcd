// The dashboard's overview: sampled once a second on an io_ thread from the copies each part
// publishes (the matches' stats after every tick, the channels' atomic counters, the DB queue),
// never on a match's strand; served as JSON and pushed to every open stream of it.
#include <chrono>

#include "admin_http.h"
#include "chat_limiter.h"
#include "control_server.h"
#include "game_channel.h"
#include "match_registry.h"
#include "ricochet/db/db_worker.h"
#include "server.h"
#include "steady_time.h"

namespace ricochet::server {

namespace {

constexpr std::chrono::seconds kOverviewPeriod{1};

OverviewMatch overview_of(const MatchHost& host) {
  const MatchHostStats stats = host.stats();
  const stats::Summary ticks = host.tick_summary();
  OverviewMatch match{.id = host.id(),
                      .name = host.name(),
                      .map = host.map_name(),
                      .mode = name(host.mode()),
                      .phase = name(stats.phase),
                      .seated = stats.seated,
                      .connected = stats.connected,
                      .max_players = host.max_players(),
                      .leader = stats.leader,
                      .leader_score = stats.leader_score,
                      .time_left_s = std::nullopt,
                      .tick_p50_ms = ticks.p50 * 1000,
                      .tick_p99_ms = ticks.p99 * 1000,
                      .overruns = stats.counters.overruns};
  if (stats.phase_ends_tick > stats.tick) {
    match.time_left_s =
        static_cast<double>(stats.phase_ends_tick - stats.tick) / host.tick_rate_hz();
  }
  return match;
}

}  // namespace

OverviewSample Server::overview_sample() const {
  OverviewSample sample;
  std::array<std::uint64_t, kJoinRefusalCount> join_refusals{};
  std::array<std::uint64_t, kInputDropCount> input_drops{};
  for (const auto& host : matches_->hosts()) {
    sample.matches.push_back(overview_of(*host));
    const MatchCounters counters = host->stats().counters;
    for (std::size_t i = 0; i < kJoinRefusalCount; ++i)
      join_refusals[i] += counters.join_refusals[i];
    for (std::size_t i = 0; i < kInputDropCount; ++i) input_drops[i] += counters.input_drops[i];
  }
  sample.players = matches_->seats();
  const proto::TransportCounters game = game_->counters();
  const ControlStats control = control_->stats();
  sample.bytes_in = game.bytes_in + control.bytes_in;
  sample.bytes_out = game.bytes_out + control.bytes_out;
  sample.db_queue_depth = db_->queued();
  sample.fleet = placement_ != nullptr;
  auto& refusals = sample.refusals;
  for (std::size_t i = 0; i < proto::kDropReasonCount; ++i) {
    refusals.push_back(
        {"game", std::string(proto::name(static_cast<proto::DropReason>(i))), game.drops[i]});
  }
  for (std::size_t i = 0; i < kControlRefusalCount; ++i) {
    refusals.push_back({"control", name(static_cast<ControlRefusal>(i)), control.refusals[i]});
  }
  for (std::size_t i = 0; i < kSeatRefusalCount; ++i) {
    const auto refusal = static_cast<SeatRefusal>(i);
    refusals.push_back({"seat", name(refusal), matches_->refused(refusal)});
  }
  for (std::size_t i = 0; i < kJoinRefusalCount; ++i) {
    refusals.push_back({"join", name(static_cast<JoinRefusal>(i)), join_refusals[i]});
  }
  for (std::size_t i = 0; i < kInputDropCount; ++i) {
    const auto drop = static_cast<InputDrop>(i);
    refusals.push_back({"input", name(drop), input_drops[i], drop == InputDrop::Stale});
  }
  const auto chat = chat_limiter_->refusals();
  for (std::size_t i = 0; i < kChatLimitCount; ++i) {
    refusals.push_back({"chat", name(static_cast<ChatLimit>(i)), chat[i]});
  }
  for (std::size_t i = 0; i < kAdminRejectReasonCount; ++i) {
    const auto reason = static_cast<AdminRejectReason>(i);
    refusals.push_back({"admin", name(reason), admin_->rejected(reason)});
  }
  return sample;
}

void Server::register_dashboard() {
  AdminRoute latest;
  latest.path = "/api/overview";
  latest.handler = [this](const AdminRequest&, AdminAnswer answer) {
    std::string json;
    {
      const std::lock_guard lock(overview_mutex_);
      json = overview_json_;
    }
    if (json.empty()) {
      answer({503, "no overview yet\n"});
    } else {
      answer({200, std::move(json), "application/json"});
    }
  };
  admin_->add_route(std::move(latest));
  AdminRoute events;
  events.path = "/api/overview/events";
  events.stream = [this](const AdminRequest&, std::shared_ptr<AdminEventStream> stream) {
    const std::lock_guard lock(overview_mutex_);
    if (!overview_json_.empty()) stream->push(overview_json_);
    overview_streams_.push_back(std::move(stream));
  };
  admin_->add_route(std::move(events));
}

void Server::sample_overview() {
  std::string json = overview_.update(steady_now_us(), overview_sample());
  {
    const std::lock_guard lock(overview_mutex_);
    std::erase_if(overview_streams_, [&json](const std::shared_ptr<AdminEventStream>& stream) {
      return !stream->push(json);
    });
    overview_json_ = std::move(json);
  }
  overview_timer_.expires_after(kOverviewPeriod);
  overview_timer_.async_wait([this](const boost::system::error_code& error) {
    if (error || stopping_) return;  // cancelled, or stopping
    sample_overview();
  });
}

}  // namespace ricochet::server
