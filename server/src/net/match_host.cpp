#include "match_host.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <boost/asio/as_tuple.hpp>
#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <chrono>
#include <numeric>
#include <string_view>
#include <utility>

#include "recording_files.h"
#include "ricochet/server/match_record.h"
#include "steady_time.h"
#include "tick_wake.h"

namespace ricochet::server {
namespace asio = boost::asio;

namespace {

constexpr proto::TimeUs kSweepIntervalUs = proto::kMicrosPerSecond;

db::UnixMillis unix_now_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

/// The phases of TickProfile as they appear in ricochet_tick_phase_seconds{phase}.
constexpr std::array<const char*, 9> kPhaseNames = {"apply_inputs", "rules",   "movement",
                                                    "combat",       "physics", "history",
                                                    "snapshots",    "send",    "total"};
constexpr const char* kPhaseHelp = "Time one tick spends in each phase, per match";
constexpr std::size_t kTickWindowTicks = 600;  ///< 10 s at 60 Hz

std::array<double, kPhaseNames.size()> phase_ms(const TickProfile& profile) {
  return {profile.apply_inputs_ms, profile.rules_ms,   profile.movement_ms,
          profile.combat_ms,       profile.physics_ms, profile.history_ms,
          profile.snapshots_ms,    profile.send_ms,    profile.total_ms};
}

}  // namespace

MatchHost::MatchHost(asio::io_context& io, Match match, GameChannel& channel, SeatReleased released,
                     MatchEndedHandler ended, RecordingFiles* recordings)
    : match_(std::move(match)),
      channel_(channel),
      released_(std::move(released)),
      on_ended_(std::move(ended)),
      recordings_(recordings),
      strand_(asio::make_strand(io)),
      timer_(strand_),
      id_(match_.id()),
      name_(match_.name()),
      map_name_(match_.map_name()),
      mode_(match_.config().rules.mode),
      max_players_(match_.max_players()),
      tick_rate_hz_(match_.config().tick.rate_hz),
      snapshot_rate_hz_(match_.config().snapshot_rate_hz),
      quantization_(match_.config().quantization),
      started_unix_ms_(unix_now_ms()),
      recording_part_(RecordingFiles::part_name(id_, started_unix_ms_)),
      tick_window_(kTickWindowTicks) {
  // 10 µs .. ~20 ms: a 60 Hz tick has 16.7 ms.
  const std::vector<double> bounds = exponential_buckets(0.00001, 2, 12);
  for (std::size_t phase = 0; phase < kPhaseNames.size(); ++phase) {
    phase_histograms_.push_back(std::make_unique<Histogram>(bounds));
  }
  match_.set_log([id = id_](std::string_view line) { spdlog::info("match {}: {}", id, line); });
  // A match that opens (at a rotation, while the server runs) is healthy until its first tick.
  stats_.last_tick_at = steady_now_us();
}

MatchHost::~MatchHost() = default;

std::shared_ptr<LiveFeed> MatchHost::live_feed(const LiveFeedConfig& config) {
  const std::lock_guard lock(live_mutex_);
  if (!live_feed_) {
    live_feed_ = std::make_shared<LiveFeed>(config);
    asio::post(strand_, [self = shared_from_this(), feed = live_feed_] {
      self->match_.set_live_feed(feed);
    });
  }
  return live_feed_;
}

void MatchHost::start() {
  asio::co_spawn(strand_, tick_loop(shared_from_this()), asio::detached);
}

void MatchHost::end(std::function<void(EndedMatch)> done) {
  asio::post(strand_, [self = shared_from_this(), done = std::move(done)] {
    if (self->ended_) {  // it ended by itself and was handed over then
      EndedMatch nothing;
      nothing.id = self->id_;
      done(std::move(nothing));
      return;
    }
    self->ended_ = true;
    self->timer_.cancel();
    self->match_.end(wire::MATCH_END_REASON_SERVER_SHUTDOWN);  // MatchEnded to every player
    self->drain_outbox();
    done(self->ended_match(true));
  });
}

EndedMatch MatchHost::ended_match(bool aborted) {
  EndedMatch ended;
  ended.id = id_;
  ended.end_reason = match_.end_reason();
  // A match nobody ever joined has nothing to replay; its recording is not kept.
  if (!played_.empty()) ended.recording = match_.take_recording();
  for (const auto& [account, played] : played_) {
    if (played.seated) ended.seated.push_back(account);
  }
  std::sort(ended.seated.begin(), ended.seated.end());
  db::MatchRecord& record = ended.record;
  record.map = map_name_;
  record.mode = server::name(mode_);
  record.started_ms = started_unix_ms_;
  record.ended_ms = unix_now_ms();
  record.tick_rate = tick_rate_hz_;
  record.aborted = aborted;
  if (mode_ == GameMode::TeamDeathmatch) {
    const std::array<int, 3> teams = match_.team_scores();
    record.team_scores.red = teams[static_cast<std::size_t>(Team::Red)];
    record.team_scores.blue = teams[static_cast<std::size_t>(Team::Blue)];
  }
  for (const CountedPlayer& counted : counted_players(match_.scoreboard(), tick_rate_hz_)) {
    const PlayerScore& score = counted.score;
    db::PlayerResult result;
    result.account = static_cast<db::AccountId>(score.account);
    result.team = static_cast<std::int32_t>(score.team);
    result.kills = score.kills;
    result.deaths = score.deaths;
    result.score = score.score;
    result.shots = score.shots;
    result.hits = score.hits;
    result.damage_dealt = score.damage_dealt;
    result.damage_taken = score.damage_taken;
    result.seconds_played = counted.seconds_played;
    record.players.push_back(result);
    ended.usernames.push_back(score.name);
  }
  return ended;
}

void MatchHost::connect(std::uint64_t account, std::string name, std::uint64_t seat) {
  asio::post(strand_, [self = shared_from_this(), account, name = std::move(name), seat] {
    if (self->ended_) return;
    const auto joined = self->match_.connect(account, name);
    if (const auto* refusal = std::get_if<JoinRefusal>(&joined)) {
      spdlog::info("match {}: account {} refused: {}", self->id_, account, server::name(*refusal));
      self->channel_.kick(account, proto::DisconnectReason::Kicked);
      self->released_(account, self->id_, seat);
      return;
    }
    const Joined& entered = std::get<Joined>(joined);
    spdlog::info("match {}: account {} {} as entity {}", self->id_, account,
                 entered.reconnected ? "came back" : "entered", entered.entity_id);
    Played& played = self->played_[account];
    played.seated = true;
    played.seat = seat;
    self->drain_outbox();
  });
}

void MatchHost::disconnect(std::uint64_t account) {
  asio::post(strand_, [self = shared_from_this(), account] {
    self->match_.disconnect(account, steady_now_us());
  });
}

void MatchHost::receive(std::vector<GamePayload> payloads) {
  asio::post(strand_, [self = shared_from_this(), payloads = std::move(payloads)] {
    if (self->ended_) return;
    for (const GamePayload& payload : payloads) {
      self->match_.set_latency(payload.account, payload.rtt_us / 2);
      self->match_.receive(payload.account, payload.bytes);
    }
  });
}

void MatchHost::chat(std::uint64_t account, std::string text) {
  asio::post(strand_, [self = shared_from_this(), account, text = std::move(text)] {
    if (const auto dropped = self->match_.chat(account, text)) {
      spdlog::debug("match {}: chat from account {} dropped: {}", self->id_, account,
                    server::name(*dropped));
    }
    self->drain_outbox();
  });
}

void MatchHost::leave(std::uint64_t account) {
  asio::post(strand_, [self = shared_from_this(), account] {
    if (const auto found = self->played_.find(account); found != self->played_.end()) {
      found->second.seated = false;  // the directory released the seat itself
    }
    if (self->match_.leave(account)) self->drain_outbox();
  });
}

MatchHostStats MatchHost::stats() const {
  const std::lock_guard lock(stats_mutex_);
  return stats_;
}

void MatchHost::report_phases(MetricsSink& sink) const {
  for (std::size_t phase = 0; phase < kPhaseNames.size(); ++phase) {
    sink.histogram("ricochet_tick_phase_seconds", kPhaseHelp,
                   {{"match", std::to_string(id_)}, {"phase", kPhaseNames[phase]}},
                   phase_histograms_[phase]->snapshot());
  }
  const stats::Summary ticks = tick_summary();
  // The quantiles are the window's; the sum and count every tick's, from the "total" phase.
  static_assert(std::string_view{kPhaseNames.back()} == "total");
  const HistogramSnapshot total = phase_histograms_.back()->snapshot();
  SummarySnapshot summary{
      .quantiles = {{0.5, ticks.p50}, {0.95, ticks.p95}, {0.99, ticks.p99}, {1.0, ticks.max}},
      .sum = total.sum,
      .count = std::accumulate(total.bucket_counts.begin(), total.bucket_counts.end(),
                               std::uint64_t{0})};
  sink.summary("ricochet_tick_seconds",
               "Tick time quantiles (nearest rank) over the match's last 600 ticks (1: the max), "
               "and the time and count of all its ticks, per match",
               {{"match", std::to_string(id_)}}, summary);
}

asio::awaitable<void> MatchHost::tick_loop(std::shared_ptr<MatchHost> self) {
  // `self` keeps the host alive while the loop runs: the tick that ends the match hands it to
  // the registry, which lets go of it.
  (void)self;
  while (!ended_) {
    tick(steady_now_us());
    if (ended_) break;
    timer_.expires_at(steady_time_point(tick_wake_at(match_.next_tick_at(), tick_rate_hz_)));
    auto [error] = co_await timer_.async_wait(asio::as_tuple(asio::use_awaitable));
    if (error) break;
  }
}

void MatchHost::tick(proto::TimeUs now) {
  if (match_.tick(now) > 0) observe_profile(match_.profile());
  drain_outbox();  // with the MatchEnded of a match that just ended
  if (match_.ended()) {
    ended_ = true;
    publish_stats(now);
    spdlog::info("match {} ended: {} after {} steps", id_,
                 wire::MatchEndReason_Name(match_.end_reason()), match_.tick_number());
    on_ended_(ended_match(false));
    return;
  }
  stream_recording();
  if (now >= next_sweep_at_) {
    sweep_departed();
    next_sweep_at_ = now + kSweepIntervalUs;
  }
  publish_stats(now);
}

void MatchHost::drain_outbox() {
  // One post for the tick's whole outbox: its snapshots leave the socket together.
  std::vector<Outgoing> batch;
  batch.reserve(match_.outbox_size());  // one allocation, not a doubling series per tick
  Outgoing outgoing;
  while (match_.poll_outbox(outgoing)) batch.push_back(std::move(outgoing));
  if (!batch.empty()) channel_.send_all(std::move(batch));
}

void MatchHost::stream_recording() {
  if (!recordings_ || played_.empty() || !recordings_->has_room()) return;
  recordings_->append(recording_part_, match_.take_recording_chunks());
}

void MatchHost::observe_profile(const TickProfile& profile) {
  const auto ms = phase_ms(profile);
  for (std::size_t phase = 0; phase < ms.size(); ++phase) {
    phase_histograms_[phase]->observe(ms[phase] / 1000.0);
  }
  const std::lock_guard lock(stats_mutex_);
  tick_window_.record(profile.total_ms / 1000.0);
}

void MatchHost::sweep_departed() {
  for (auto& [account, played] : played_) {
    if (!played.seated || match_.entity_of(account)) continue;
    played.seated = false;
    released_(account, id_, played.seat);
  }
}

void MatchHost::publish_stats(proto::TimeUs now) {
  const std::lock_guard lock(stats_mutex_);
  stats_.counters = match_.counters();
  stats_.last_profile = match_.profile();
  stats_.seated = match_.player_count();
  stats_.connected = match_.connected_count();
  stats_.last_tick_at = now;
  stats_.phase = match_.phase();
  stats_.tick = match_.tick_number();
  stats_.phase_ends_tick = match_.phase_ends_tick();
  if (stats_.tick >= next_leader_tick_) {
    find_leader();
    next_leader_tick_ = stats_.tick + static_cast<std::uint32_t>(tick_rate_hz_);
  }
}

void MatchHost::find_leader() {
  stats_.leader.clear();
  stats_.leader_score = 0;
  if (mode_ == GameMode::TeamDeathmatch) {
    const auto teams = match_.team_scores();
    const auto red = teams[static_cast<std::size_t>(Team::Red)];
    const auto blue = teams[static_cast<std::size_t>(Team::Blue)];
    if (red != blue) {
      stats_.leader = red > blue ? "red" : "blue";
      stats_.leader_score = std::max(red, blue);
    }
    return;
  }
  for (const PlayerScore& score : match_.scoreboard()) {
    if (score.score > stats_.leader_score) {
      stats_.leader = score.name;
      stats_.leader_score = score.score;
    }
  }
}

stats::Summary MatchHost::tick_summary() const {
  // Copied under the lock and sorted outside it: the tick waits for a copy of 600 doubles at
  // most, never for the sort.
  TickWindow window{1};
  {
    const std::lock_guard lock(stats_mutex_);
    window = tick_window_;
  }
  return window.summary();
}

}  // namespace ricochet::server
