#include "match_host.h"

#include <chrono>
#include <utility>

#include <boost/asio/as_tuple.hpp>
#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <spdlog/spdlog.h>

#include "steady_time.h"

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
constexpr std::array<const char*, 7> kPhaseNames = {
    "apply_inputs", "movement", "physics", "history", "snapshots", "send", "total"};

std::array<double, 7> phase_ms(const TickProfile& profile) {
  return {profile.apply_inputs_ms, profile.movement_ms, profile.physics_ms, profile.history_ms,
          profile.snapshots_ms,    profile.send_ms,     profile.total_ms};
}

}  // namespace

MatchHost::MatchHost(asio::io_context& io, Match match, GameChannel& channel,
                     MetricsRegistry& metrics, SeatReleased released)
    : match_(std::move(match)),
      channel_(channel),
      released_(std::move(released)),
      strand_(asio::make_strand(io)),
      timer_(strand_),
      id_(match_.id()),
      name_(match_.name()),
      map_name_(match_.map_name()),
      max_players_(match_.max_players()),
      tick_rate_hz_(match_.config().tick.rate_hz),
      snapshot_rate_hz_(match_.config().snapshot_rate_hz),
      quantization_(match_.config().quantization),
      started_unix_ms_(unix_now_ms()) {
  // 10 µs .. ~20 ms: a 60 Hz tick has 16.7 ms.
  const std::vector<double> bounds = exponential_buckets(0.00001, 2, 12);
  for (std::size_t phase = 0; phase < kPhaseNames.size(); ++phase) {
    phase_histograms_[phase] = &metrics.histogram(
        "ricochet_tick_phase_seconds", "Time one tick spends in each phase, per match", bounds,
        {{"match", std::to_string(id_)}, {"phase", kPhaseNames[phase]}});
  }
}

MatchHost::~MatchHost() = default;

void MatchHost::start() { asio::co_spawn(strand_, tick_loop(), asio::detached); }

void MatchHost::end(std::function<void(EndedMatch)> done) {
  asio::post(strand_, [self = shared_from_this(), done = std::move(done)] {
    const proto::TimeUs now = steady_now_us();
    self->ended_ = true;
    self->timer_.cancel();
    self->match_.end(wire::MATCH_END_REASON_SERVER_SHUTDOWN);  // MatchEnded to every player
    self->drain_outbox();
    EndedMatch ended;
    ended.id = self->id_;
    ended.end_reason = wire::MATCH_END_REASON_SERVER_SHUTDOWN;
    db::MatchRecord& record = ended.record;
    record.map = self->map_name_;
    record.mode = "ffa";
    record.started_ms = self->started_unix_ms_;
    record.ended_ms = unix_now_ms();
    record.tick_rate = self->tick_rate_hz_;
    record.aborted = true;  // stopped by the server before its end
    for (auto& [account, played] : self->played_) {
      played.stop(now);
      db::PlayerResult result;
      result.account = static_cast<db::AccountId>(account);
      result.seconds_played = played.seconds;
      record.players.push_back(result);
      ended.usernames.push_back(played.username);
    }
    done(std::move(ended));
  });
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
    played.username = name;
    played.seated = true;
    played.seat = seat;
    if (played.connected_at == 0) played.connected_at = steady_now_us();
    self->drain_outbox();
  });
}

void MatchHost::disconnect(std::uint64_t account) {
  asio::post(strand_, [self = shared_from_this(), account] {
    const proto::TimeUs now = steady_now_us();
    self->match_.disconnect(account, now);
    self->stop_playing(account, now);
  });
}

void MatchHost::receive(std::uint64_t account, std::vector<std::uint8_t> payload) {
  asio::post(strand_, [self = shared_from_this(), account, payload = std::move(payload)] {
    self->match_.receive(account, payload);
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
    const proto::TimeUs now = steady_now_us();
    self->stop_playing(account, now);
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

asio::awaitable<void> MatchHost::tick_loop() {
  while (!ended_) {
    tick(steady_now_us());
    timer_.expires_at(steady_time_point(match_.next_tick_at()));
    auto [error] = co_await timer_.async_wait(asio::as_tuple(asio::use_awaitable));
    if (error) break;
  }
}

void MatchHost::tick(proto::TimeUs now) {
  if (match_.tick(now) > 0) observe_profile(match_.profile());
  drain_outbox();
  if (now >= next_sweep_at_) {
    sweep_departed();
    next_sweep_at_ = now + kSweepIntervalUs;
  }
  publish_stats(now);
}

void MatchHost::drain_outbox() {
  Outgoing outgoing;
  while (match_.poll_outbox(outgoing)) {
    channel_.send(outgoing.account, outgoing.reliable, std::move(outgoing.bytes));
  }
}

void MatchHost::observe_profile(const TickProfile& profile) {
  const std::array<double, 7> ms = phase_ms(profile);
  for (std::size_t phase = 0; phase < ms.size(); ++phase) {
    phase_histograms_[phase]->observe(ms[phase] / 1000.0);
  }
}

void MatchHost::sweep_departed() {
  const proto::TimeUs now = steady_now_us();
  for (auto& [account, played] : played_) {
    if (!played.seated || match_.entity_of(account)) continue;
    played.seated = false;
    stop_playing(account, now);
    released_(account, id_, played.seat);
  }
}

void MatchHost::stop_playing(std::uint64_t account, proto::TimeUs now) {
  const auto found = played_.find(account);
  if (found != played_.end()) found->second.stop(now);
}

void MatchHost::publish_stats(proto::TimeUs now) {
  const std::lock_guard lock(stats_mutex_);
  stats_.counters = match_.counters();
  stats_.last_profile = match_.profile();
  stats_.seated = match_.player_count();
  stats_.connected = match_.connected_count();
  stats_.last_tick_at = now;
}

}  // namespace ricochet::server
