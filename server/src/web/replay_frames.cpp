/// A recording re-simulated into frames a viewer can jump around in (replay_frames.h).

#include "replay_frames.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <utility>

#include "ricochet/proto/entity_flags.h"
#include "ricochet/server/match.h"
#include "ricochet/server/match_replay.h"
#include "ricochet/tools/json_text.h"

namespace ricochet::server {

namespace {

/// The Match, and the yaw of each entity's last input (the positions come from the Match).
class ViewedSimulation final : public ReplaySimulation {
 public:
  explicit ViewedSimulation(Match& match) : inner_(match) {}
  void apply(const RecordedEvent& event) override { inner_.apply(event); }
  void step(std::span<const RecordedInput> inputs) override {
    for (const RecordedInput& input : inputs) yaw_[input.entity_id] = input.input.yaw_rad;
    inner_.step(inputs);
  }
  std::uint64_t state_hash() const override { return inner_.state_hash(); }
  float yaw_of(std::uint32_t entity) const {
    const auto it = yaw_.find(entity);
    return it == yaw_.end() ? 0.0f : it->second;
  }

 private:
  MatchSimulation inner_;
  std::map<std::uint32_t, float> yaw_;
};

struct Tally {
  std::int32_t kills = 0, deaths = 0, score = 0;
  friend bool operator==(const Tally&, const Tally&) = default;
};

/// %.9g, as ricochet-replay --export prints a float; null for what JSON cannot hold.
void append_number(std::string& out, float value) {
  if (!std::isfinite(value)) {
    out += "null";
    return;
  }
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", static_cast<double>(value));
  out += text;
}

void append_score(std::string& out, std::uint32_t entity, const Tally& tally) {
  out += "{\"entity\":" + std::to_string(entity) + ",\"kills\":" + std::to_string(tally.kills) +
         ",\"deaths\":" + std::to_string(tally.deaths) +
         ",\"score\":" + std::to_string(tally.score) + "}";
}

}  // namespace

std::size_t ReplayFrames::bytes() const {
  std::size_t total = sizeof(*this) + tick_start.capacity() * sizeof(std::uint32_t) +
                      entities.capacity() * sizeof(FrameEntity) +
                      kills.capacity() * sizeof(FrameKill) +
                      scores.capacity() * sizeof(FrameScore) + cut.capacity();
  for (const ReplayPlayer& player : players) total += sizeof(player) + player.name.capacity();
  return total;
}

std::variant<ReplayFrames, std::string> replay_frames(const Recording& recording,
                                                      ReplayProgress& progress,
                                                      std::size_t max_bytes) {
  auto opened = open_recorded_match(recording);
  if (auto* bad = std::get_if<std::string>(&opened)) return std::move(*bad);
  Match& match = std::get<Match>(opened);
  ViewedSimulation simulation(match);
  ReplayFrames frames;
  frames.tick_rate_hz = recording.header.tick_rate_hz;
  if (!recording.complete) frames.cut = recording.cut;
  // The frames grow by about the same every tick: reserve for the whole recording when it fits.
  const std::size_t ticks = recording.ticks.empty() ? 0 : recording.ticks.back().tick;
  frames.tick_start.reserve(ticks + 1);

  match.observe_events([&](const wire::GameEvent& event) {
    if (!event.has_kill()) return;
    const wire::Kill& kill = event.kill();
    frames.kills.push_back({frames.last_tick + 1, kill.tick(), kill.killer_entity_id(),
                            kill.victim_entity_id(), static_cast<std::uint8_t>(kill.weapon())});
  });
  std::map<std::uint32_t, Tally> tallies;  // by entity: the last scores kept
  bool over_budget = false;
  ReplayOptions options;
  options.after_step = [&](std::uint32_t tick) {
    frames.last_tick = tick;
    const std::vector<PlayerScore> scoreboard = match.scoreboard();
    for (const proto::EntityState& state : match.entity_states()) {
      FrameEntity entity;
      entity.id = state.id;
      entity.position_m = state.position_m;
      entity.flags = state.flags;
      if ((state.flags & proto::kEntityKindMask) == 0) {
        entity.yaw_rad = simulation.yaw_of(state.id);
        const auto seated =
            std::find_if(scoreboard.begin(), scoreboard.end(),
                         [&](const PlayerScore& s) { return s.entity_id == state.id; });
        if (seated != scoreboard.end()) {
          if (const auto view = match.player_view(seated->account)) {
            entity.health =
                static_cast<std::int16_t>(std::clamp(view->vitals.health, -32768, 32767));
          }
        }
      }
      frames.entities.push_back(entity);
    }
    frames.tick_start.push_back(static_cast<std::uint32_t>(frames.entities.size()));
    for (const PlayerScore& s : scoreboard) {
      const Tally now{s.kills, s.deaths, s.score};
      auto [it, added] = tallies.try_emplace(s.entity_id, Tally{});
      if (added && now == Tally{}) continue;
      if (!added && it->second == now) continue;
      it->second = now;
      frames.scores.push_back({tick, s.entity_id, now.kills, now.deaths, now.score});
    }
    progress.ticks_done.store(tick, std::memory_order_relaxed);
    over_budget = frames.bytes() > max_bytes;
    if (progress.after_step) progress.after_step(tick);
  };
  options.stop_requested = [&] {
    return over_budget || progress.stop.load(std::memory_order_relaxed);
  };
  frames.report = replay(recording, simulation, options);
  if (over_budget) {
    return "the replay needs more than " + std::to_string(max_bytes) + " bytes at tick " +
           std::to_string(frames.last_tick) + " (raise dashboard.replay_memory_mb)";
  }
  if (frames.report.stopped) return std::string("stopped");
  for (const PlayerScore& s : match.scoreboard()) {
    frames.players.push_back({s.account, s.name, s.entity_id, static_cast<std::uint8_t>(s.team)});
  }
  frames.tick_start.shrink_to_fit();
  frames.entities.shrink_to_fit();
  return frames;
}

std::string frames_json(const ReplayFrames& frames, std::uint32_t first, std::uint32_t end,
                        std::string& error) {
  if (first < 1 || end <= first || end > frames.last_tick + 1 ||
      end - first > kMaxFramesPerRequest) {
    error = "ticks [first, end) must be within 1.." + std::to_string(frames.last_tick + 1) +
            ", first < end, at most " + std::to_string(kMaxFramesPerRequest) + " of them; got [" +
            std::to_string(first) + ", " + std::to_string(end) + ")";
    return {};
  }
  error.clear();
  std::string out = "{\"first_tick\":" + std::to_string(first) +
                    ",\"end_tick\":" + std::to_string(end) +
                    ",\"tick_rate_hz\":" + std::to_string(frames.tick_rate_hz) + ",\"scores\":[";
  std::map<std::uint32_t, Tally> before;
  auto score = frames.scores.begin();
  for (; score != frames.scores.end() && score->tick < first; ++score)
    before[score->entity] = {score->kills, score->deaths, score->score};
  bool comma = false;
  for (const auto& [entity, tally] : before) {
    if (comma) out += ',';
    comma = true;
    append_score(out, entity, tally);
  }
  out += "],\"frames\":[";
  auto kill = std::lower_bound(frames.kills.begin(), frames.kills.end(), first,
                               [](const FrameKill& k, std::uint32_t t) { return k.tick < t; });
  for (std::uint32_t tick = first; tick < end; ++tick) {
    if (tick != first) out += ',';
    out += "{\"tick\":" + std::to_string(tick) + ",\"players\":[";
    std::string projectiles;
    bool player_comma = false;
    for (std::uint32_t i = frames.tick_start[tick - 1]; i < frames.tick_start[tick]; ++i) {
      const FrameEntity& e = frames.entities[i];
      const auto kind = proto::entity_kind(e.flags);
      std::string item = "{\"id\":" + std::to_string(e.id);
      if (kind && *kind != proto::EntityKind::Player) {
        item += ",\"kind\":";
        item += *kind == proto::EntityKind::Rocket ? "\"rocket\"" : "\"grenade\"";
      }
      item += ",\"x\":";
      append_number(item, e.position_m[0]);
      item += ",\"y\":";
      append_number(item, e.position_m[1]);
      item += ",\"z\":";
      append_number(item, e.position_m[2]);
      if (kind == proto::EntityKind::Player) {
        item += ",\"yaw\":";
        append_number(item, e.yaw_rad);
        item += ",\"health\":" + std::to_string(e.health);
        item += ",\"alive\":";
        item += (e.flags & proto::kEntityDead) ? "false" : "true";
        item += ",\"away\":";
        item += (e.flags & proto::kEntityDisconnected) ? "true" : "false";
        item += '}';
        if (player_comma) out += ',';
        player_comma = true;
        out += item;
      } else {
        item += '}';
        if (!projectiles.empty()) projectiles += ',';
        projectiles += item;
      }
    }
    out += "],\"projectiles\":[" + projectiles + "],\"kills\":[";
    for (bool kill_comma = false; kill != frames.kills.end() && kill->tick == tick; ++kill) {
      if (kill_comma) out += ',';
      kill_comma = true;
      out += "{\"killer\":" + std::to_string(kill->killer) +
             ",\"victim\":" + std::to_string(kill->victim) +
             ",\"weapon\":" + std::to_string(kill->weapon) +
             ",\"tick\":" + std::to_string(kill->event_tick) + "}";
    }
    out += "],\"scores\":[";
    for (bool score_comma = false; score != frames.scores.end() && score->tick == tick; ++score) {
      if (score_comma) out += ',';
      score_comma = true;
      append_score(out, score->entity, {score->kills, score->deaths, score->score});
    }
    out += "]}";
  }
  out += "]}";
  return out;
}

std::string replay_summary_json(const ReplayFrames& frames) {
  const ReplayReport& report = frames.report;
  std::string out = "{\"last_tick\":" + std::to_string(frames.last_tick);
  out += ",\"tick_rate_hz\":" + std::to_string(frames.tick_rate_hz);
  char seconds[32];
  std::snprintf(
      seconds, sizeof seconds, "%.3f",
      frames.tick_rate_hz ? static_cast<double>(frames.last_tick) / frames.tick_rate_hz : 0.0);
  out += ",\"seconds\":";
  out += seconds;
  out += ",\"complete\":";
  out += report.complete ? "true" : "false";
  out += ",\"cut\":" + (report.complete ? std::string("null") : tools::json_string(frames.cut));
  out += ",\"truncated\":";
  out += report.truncated ? "true" : "false";
  out += ",\"hashes_checked\":" + std::to_string(report.hashes_checked);
  out += ",\"hashes_matched\":";
  out += report.first_mismatch ? "false" : "true";
  out +=
      ",\"first_mismatch_tick\":" +
      (report.first_mismatch ? std::to_string(report.first_mismatch->tick) : std::string("null"));
  out += ",\"kills\":" + std::to_string(frames.kills.size());
  out += ",\"players\":[";
  for (std::size_t i = 0; i < frames.players.size(); ++i) {
    const ReplayPlayer& p = frames.players[i];
    if (i) out += ',';
    out += "{\"account\":" + std::to_string(p.account) + ",\"name\":" + tools::json_string(p.name) +
           ",\"entity\":" + std::to_string(p.entity) + ",\"team\":" + std::to_string(p.team) + "}";
  }
  out += "]}";
  return out;
}

}  // namespace ricochet::server
