/// A live frame as JSON, and a viewer's stream of them (frame_json.h).

#include "frame_json.h"

#include "json_out.h"

namespace ricochet::server::web {

namespace {

void append_bool(std::string& out, bool value) {
  out += value ? "true" : "false";
}

void append_player(std::string& out, const LivePlayer& player) {
  out += "{\"id\":" + std::to_string(player.entity_id) + ",\"name\":";
  append_string(out, player.name);
  out += ",\"team\":";
  append_team(out, player.team);
  out += ",\"position\":";
  append_vec3(out, player.position_m);
  out += ",\"velocity\":";
  append_vec3(out, player.velocity_mps, 2);
  out += ",\"yaw\":";
  append_number(out, player.yaw_rad, 4);
  out += ",\"health\":" + std::to_string(player.health);
  out += ",\"armor\":" + std::to_string(player.armor);
  out += ",\"alive\":";
  append_bool(out, player.alive);
  out += ",\"connected\":";
  append_bool(out, player.connected);
  out += ",\"weapon\":\"";
  out += name(player.weapon);
  out += "\",\"kills\":" + std::to_string(player.kills);
  out += ",\"deaths\":" + std::to_string(player.deaths);
  out += ",\"score\":" + std::to_string(player.score) + '}';
}

void append_projectile(std::string& out, const LiveProjectile& shot) {
  out += "{\"id\":" + std::to_string(shot.entity_id) + ",\"kind\":\"";
  out += name(shot.kind);
  out += "\",\"owner\":" + std::to_string(shot.owner_entity_id) + ",\"position\":";
  append_vec3(out, shot.position_m);
  out += ",\"velocity\":";
  append_vec3(out, shot.velocity_mps, 2);
  out += '}';
}

void append_kill(std::string& out, const LiveKill& kill) {
  out += "{\"tick\":" + std::to_string(kill.tick);
  out += ",\"killer\":" + std::to_string(kill.killer_entity_id);
  out += ",\"victim\":" + std::to_string(kill.victim_entity_id) + ",\"weapon\":";
  if (kill.weapon) {
    out += '"';
    out += name(*kill.weapon);
    out += '"';
  } else {
    out += "null";
  }
  out += '}';
}

}  // namespace

std::string frame_json(const LiveFrame& frame) {
  std::string out;
  out.reserve(256 + 256 * frame.players.size() + 128 * frame.projectiles.size());
  out += "{\"match\":" + std::to_string(frame.match_id);
  out += ",\"tick\":" + std::to_string(frame.tick);
  out += ",\"server_time_us\":" + std::to_string(frame.server_time_us);
  out += ",\"tick_rate_hz\":" + std::to_string(frame.tick_rate_hz);
  out += ",\"phase\":\"";
  out += name(frame.phase);
  out += "\",\"time_left_s\":";
  if (frame.time_left_s) {
    append_number(out, *frame.time_left_s, 2);
  } else {
    out += "null";
  }
  out += ",\"mode\":\"";
  out += name(frame.mode);
  out += "\",\"team_scores\":{\"red\":" + std::to_string(frame.team_scores[1]) +
         ",\"blue\":" + std::to_string(frame.team_scores[2]) + "},\"players\":";
  append_array(out, frame.players, append_player);
  out += ",\"projectiles\":";
  append_array(out, frame.projectiles, append_projectile);
  out += ",\"kills\":";
  append_array(out, frame.kills, append_kill);
  out += ",\"kills_dropped\":" + std::to_string(frame.kills_dropped) + '}';
  return out;
}

std::optional<std::string> FrameStream::next() {
  std::shared_ptr<const LiveFrame> frame = viewer_.latest();
  if (!frame || frame == last_) return std::nullopt;
  last_ = std::move(frame);
  return frame_json(*last_);
}

}  // namespace ricochet::server::web
