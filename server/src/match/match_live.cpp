/// A match's live frames (match_live.h): copied from the parts after the tick's steps, published
/// at the feed's rate while someone watches.

#include "match_live.h"

namespace ricochet::server {

namespace {

std::array<float, 3> to_array(const physics::Vec3& v) {
  return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
}

}  // namespace

void LiveKills::note(const LiveKill& kill) {
  if (kills.size() < kMaxLiveKills) {
    kills.push_back(kill);
  } else {
    ++dropped;
  }
}

void publish_live_frame(proto::TimeUs now, const MatchConfig& config, std::uint32_t tick,
                        const Roster& roster, const Combat& combat, const RulesState& rules,
                        LiveTap& tap) {
  tap.last_tick_us = now;
  if (!tap.feed || !tap.feed->watched()) {
    tap.kills = LiveKills{};
    tap.next_frame_us = now;  // the first viewer gets a frame at the next tick
    return;
  }
  if (tap.ended_shown || (now < tap.next_frame_us && !rules.ended())) return;
  tap.ended_shown = rules.ended();
  tap.next_frame_us += tap.feed->interval_us();
  if (tap.next_frame_us <= now) tap.next_frame_us = now + tap.feed->interval_us();

  auto frame = std::make_shared<LiveFrame>();
  frame->match_id = config.id;
  frame->tick = tick;
  frame->server_time_us = now;
  frame->tick_rate_hz = config.tick.rate_hz;
  frame->phase = rules.phase;
  if (rules.phase_ends_tick != 0 && !rules.ended()) {
    const std::uint32_t left = rules.phase_ends_tick > tick ? rules.phase_ends_tick - tick : 0;
    frame->time_left_s = static_cast<double>(left) / config.tick.rate_hz;
  }
  frame->mode = config.rules.mode;
  frame->team_scores = rules.team_scores;
  frame->players.reserve(roster.players.size());
  for (const Player& player : roster.players) {
    LivePlayer& out = frame->players.emplace_back();
    out.entity_id = player.entity_id;
    out.name = player.name;
    out.team = player.team;
    out.position_m = to_array(player.position_m);
    out.velocity_mps = to_array(player.velocity_mps);
    out.yaw_rad = player.aim_yaw_rad;
    out.health = player.vitals.health;
    out.armor = player.vitals.armor;
    out.alive = player.alive;
    out.connected = player.connected;
    out.weapon = player.weapon;
    out.kills = player.score.kills;
    out.deaths = player.score.deaths;
    out.score = player.score.score;
  }
  frame->projectiles.reserve(combat.projectiles.size());
  for (const Projectile& shot : combat.projectiles) {
    LiveProjectile& out = frame->projectiles.emplace_back();
    out.entity_id = shot.entity_id;
    out.kind = shot.weapon == WeaponKind::GrenadeLauncher ? LiveProjectileKind::Grenade
                                                          : LiveProjectileKind::Rocket;
    out.owner_entity_id = shot.owner_entity;
    out.position_m = to_array(shot.position_m);
    out.velocity_mps = to_array(shot.velocity_mps);
  }
  frame->kills = std::move(tap.kills.kills);
  frame->kills_dropped = tap.kills.dropped;
  tap.kills = LiveKills{};
  tap.feed->publish(std::move(frame));
}

}  // namespace ricochet::server
