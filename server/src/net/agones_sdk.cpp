#include "agones_sdk.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <set>
#include <utility>

namespace ricochet::server {

const char* name(AgonesCall call) {
  switch (call) {
    case AgonesCall::Ready:
      return "ready";
    case AgonesCall::Health:
      return "health";
    case AgonesCall::Label:
      return "label";
    case AgonesCall::Allocate:
      return "allocate";
    case AgonesCall::Shutdown:
      return "shutdown";
    case AgonesCall::GameServer:
      return "gameserver";
  }
  return "unknown";
}

const char* name(AgonesOutcome outcome) {
  switch (outcome) {
    case AgonesOutcome::Ok:
      return "ok";
    case AgonesOutcome::IoError:
      return "io_error";
    case AgonesOutcome::Timeout:
      return "timeout";
    case AgonesOutcome::ServerError:
      return "http_5xx";
    case AgonesOutcome::ClientError:
      return "http_4xx";
  }
  return "unknown";
}

namespace {

bool label_character(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' ||
         c == '_' || c == '.';
}

bool alphanumeric(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9');
}

/// The distinct values, sorted, joined by '.' ("arena.foundry").
std::string distinct_joined(std::set<std::string> values) {
  std::string joined;
  for (const std::string& value : values) {
    if (!joined.empty()) joined += '.';
    joined += value;
  }
  return joined;
}

/// A JSON string literal of `text`, which label_value() made plain ([A-Za-z0-9._-]).
std::string json_string(std::string_view text) {
  std::string quoted = "\"";
  quoted += text;
  quoted += '"';
  return quoted;
}

}  // namespace

AgonesSdk::AgonesSdk(AgonesSdkConfig config) : config_(config), backoff_us_(config.retry_first_us) {
  for (const std::string_view key : kLabelKeys) labels_.emplace(std::string(key), Label{});
}

std::string AgonesSdk::label_value(std::string_view text) {
  std::string value;
  for (const char c : text) value += label_character(c) ? c : '-';
  if (value.size() > 63) value.resize(63);
  while (!value.empty() && !alphanumeric(value.back())) value.pop_back();
  const auto first = std::find_if(value.begin(), value.end(), alphanumeric);
  value.erase(value.begin(), first);
  return value;
}

void AgonesSdk::ready(proto::TimeUs now) {
  if (ready_requested_) return;
  ready_requested_ = true;
  health_due_at_ = now;
}

void AgonesSdk::observe(std::vector<AgonesMatchView> matches) {
  matches_ = std::move(matches);
  std::set<std::string> maps;
  std::set<std::string> modes;
  int players = 0;
  int capacity = 0;
  for (const AgonesMatchView& match : matches_) {
    maps.insert(match.map);
    modes.insert(match.mode);
    players += match.players;
    capacity += match.capacity;
  }
  labels_["map"].wanted = label_value(distinct_joined(std::move(maps)));
  labels_["mode"].wanted = label_value(distinct_joined(std::move(modes)));
  labels_["players"].wanted = std::to_string(players);
  labels_["capacity"].wanted = std::to_string(capacity);
  // A direct join allocates once seated (the header says why not at its join).
  if (players > 0) players_placed();
}

void AgonesSdk::players_placed() {
  if (stopping_) return;
  allocate_requested_ = true;
}

void AgonesSdk::fetch_game_server() {
  game_server_requested_ = true;
}

bool AgonesSdk::game_server_due() const {
  return game_server_requested_ && !game_server_done_ && ready_done_ && !stopping_;
}

std::optional<AgonesGameServerAnswer> AgonesSdk::take_game_server() {
  return std::exchange(game_server_answer_, std::nullopt);
}

void AgonesSdk::match_finished() {
  ++counters_.matches_finished;
  const auto limit = static_cast<std::uint64_t>(config_.shutdown_after_matches);
  if (limit == 0 || counters_.matches_finished < limit || shutdown_requested_) return;
  spdlog::info(
      "agones: {} matches finished (agones.shutdown_after_matches): asking Agones to shut this "
      "GameServer down",
      counters_.matches_finished);
  shutdown_requested_ = true;
}

void AgonesSdk::stopping() {
  stopping_ = true;
}

void AgonesSdk::drained() {
  shutdown_requested_ = true;
}

bool AgonesSdk::ticking_on_time(proto::TimeUs now) {
  if (stopping_) return true;
  std::string late;
  std::map<std::uint32_t, std::uint64_t> overruns;
  for (const AgonesMatchView& match : matches_) {
    overruns[match.id] = match.overruns;
    if (!late.empty()) continue;
    const proto::TimeUs since_tick = now - match.last_tick_at;
    if (since_tick > config_.stuck_after_us) {
      late = "match " + std::to_string(match.id) + " last ticked " +
             std::to_string(since_tick / proto::kMicrosPerMilli) + " ms ago";
      continue;
    }
    const auto before = overruns_at_last_ping_.find(match.id);
    if (before != overruns_at_last_ping_.end() && match.overruns > before->second) {
      late = "match " + std::to_string(match.id) + " overran its catch-up cap " +
             std::to_string(match.overruns - before->second) + " times";
    }
  }
  overruns_at_last_ping_ = std::move(overruns);
  if (late.empty()) {
    if (withholding_) spdlog::info("agones: every match ticks on time again; health pings resume");
    withholding_ = false;
    return true;
  }
  ++counters_.health_withheld;
  if (!withholding_) {
    spdlog::warn(
        "agones: {}: health pings withheld (after failureThreshold missed pings Agones marks "
        "this GameServer Unhealthy)",
        late);
  }
  withholding_ = true;
  return false;
}

AgonesRequest AgonesSdk::post(AgonesCall call) const {
  return AgonesRequest{call, "POST", std::string("/") + name(call), "{}"};
}

std::optional<AgonesRequest> AgonesSdk::due_label(proto::TimeUs now) {
  for (auto& [key, label] : labels_) {
    if (label.sent == label.wanted) continue;
    if (label.sent && now < label.sent_at + config_.label_interval_us) continue;
    in_flight_label_ = {key, label.wanted};
    return AgonesRequest{
        AgonesCall::Label, "PUT", "/metadata/label",
        "{\"key\":" + json_string(key) + ",\"value\":" + json_string(label.wanted) + "}"};
  }
  return std::nullopt;
}

std::optional<AgonesRequest> AgonesSdk::next_call(proto::TimeUs now) {
  if (in_flight_ || shutdown_done_ || now < retry_at_) return std::nullopt;
  std::optional<AgonesRequest> call;
  if (shutdown_requested_) {
    call = post(AgonesCall::Shutdown);
  } else if (!ready_requested_) {
    return std::nullopt;
  } else if (!ready_done_) {
    call = post(AgonesCall::Ready);
  } else if (game_server_due()) {
    call = AgonesRequest{AgonesCall::GameServer, "GET", "/gameserver", ""};
  } else if (allocate_requested_ && !allocate_done_ && !stopping_) {
    call = post(AgonesCall::Allocate);
  } else if (now >= health_due_at_ && ticking_on_time(now)) {
    call = post(AgonesCall::Health);
  } else {
    if (now >= health_due_at_) health_due_at_ = now + config_.health_interval_us;  // withheld
    if (!stopping_) call = due_label(now);
  }
  if (call) {
    in_flight_ = call;
    in_flight_since_ = now;
  }
  return call;
}

void AgonesSdk::settled(proto::TimeUs now, bool accepted, std::string_view body) {
  // A call the sidecar refused itself (4xx) is settled too: sending it again would be refused
  // again.
  switch (in_flight_->call) {
    case AgonesCall::Ready:
      ready_done_ = true;
      if (accepted) spdlog::info("agones: the GameServer is Ready");
      break;
    case AgonesCall::Health:
      health_due_at_ = in_flight_since_ + config_.health_interval_us;
      break;
    case AgonesCall::Label: {
      Label& label = labels_[in_flight_label_.first];
      label.sent = in_flight_label_.second;
      label.sent_at = now;
      break;
    }
    case AgonesCall::Allocate:
      allocate_done_ = true;
      if (accepted) spdlog::info("agones: the GameServer is Allocated");
      break;
    case AgonesCall::Shutdown:
      shutdown_done_ = true;
      if (accepted) spdlog::info("agones: the GameServer is shutting down");
      break;
    case AgonesCall::GameServer:
      game_server_done_ = true;
      game_server_answer_ = AgonesGameServerAnswer{
          accepted ? std::optional<std::string>(std::string(body)) : std::nullopt};
      break;
  }
}

void AgonesSdk::call_done(AgonesOutcome outcome, proto::TimeUs now, std::string_view body) {
  if (!in_flight_) return;
  const AgonesCall call = in_flight_->call;
  ++counters_.calls[static_cast<std::size_t>(call)][static_cast<std::size_t>(outcome)];
  switch (outcome) {
    case AgonesOutcome::Ok:
      if (failures_in_episode_ > 0) {
        spdlog::info("agones: the SDK sidecar answers again, after {} failed calls over {} ms",
                     failures_in_episode_, (now - episode_started_at_) / proto::kMicrosPerMilli);
      }
      failures_in_episode_ = 0;
      backoff_us_ = config_.retry_first_us;
      settled(now, /*accepted=*/true, body);
      break;
    case AgonesOutcome::ClientError:
      spdlog::error("agones: the SDK sidecar refused {} {} {} ({}); not sent again",
                    in_flight_->method, in_flight_->path, in_flight_->body, name(outcome));
      settled(now, /*accepted=*/false, {});
      break;
    case AgonesOutcome::IoError:
    case AgonesOutcome::Timeout:
    case AgonesOutcome::ServerError:
      if (failures_in_episode_++ == 0) {
        episode_started_at_ = now;
        spdlog::warn(
            "agones: {} {} to the SDK sidecar failed ({}); retrying with back-off from {} ms to "
            "{} ms (the sidecar may still be starting); logged again when it answers",
            in_flight_->method, in_flight_->path, name(outcome),
            config_.retry_first_us / proto::kMicrosPerMilli,
            config_.retry_last_us / proto::kMicrosPerMilli);
      }
      retry_at_ = now + backoff_us_;
      backoff_us_ = std::min(backoff_us_ * 2, config_.retry_last_us);
      break;
  }
  in_flight_.reset();
}

std::optional<proto::TimeUs> AgonesSdk::next_due(proto::TimeUs now) const {
  if (in_flight_ || shutdown_done_) return std::nullopt;
  if (now < retry_at_) return retry_at_;
  if (shutdown_requested_) return now;
  if (!ready_requested_) return std::nullopt;
  if (!ready_done_ || game_server_due() || (allocate_requested_ && !allocate_done_ && !stopping_)) {
    return now;
  }
  proto::TimeUs due = health_due_at_;
  if (!stopping_) {
    for (const auto& [key, label] : labels_) {
      if (label.sent == label.wanted) continue;
      due = std::min(due, label.sent ? label.sent_at + config_.label_interval_us : now);
    }
  }
  return std::max(due, now);
}

}  // namespace ricochet::server
