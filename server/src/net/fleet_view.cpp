#include "fleet_view.h"

#include <boost/json.hpp>
#include <map>

namespace ricochet::server {

std::string fleet_json(const db::FleetDirectory& directory, std::string_view self_id,
                       db::UnixMillis now_ms) {
  namespace json = boost::json;
  std::map<std::string_view, json::array> matches_of;
  for (const db::GameServerRow& row : directory.servers) matches_of[row.server_id];
  for (const db::DirectoryMatch& listed : directory.matches) {
    const auto server = matches_of.find(listed.server_id);
    if (server == matches_of.end()) continue;
    const db::HostedMatch& m = listed.match;
    server->second.push_back(json::object{{"match_id", m.match_id},
                                          {"mode", m.mode},
                                          {"map", m.map},
                                          {"players", m.players},
                                          {"capacity", m.capacity},
                                          {"open", m.open}});
  }
  json::array servers;
  for (const db::GameServerRow& row : directory.servers) {
    json::object server{{"server_id", row.server_id},
                        {"self", row.server_id == self_id},
                        {"host", row.host},
                        {"control_port", row.control_port},
                        {"game_port", row.game_port},
                        {"admin_port", nullptr},
                        {"certificate_sha256", row.certificate_sha256},
                        {"version", row.version},
                        {"capacity", row.capacity},
                        {"players", row.players},
                        {"heartbeat_age_ms", now_ms - row.heartbeat_ms},
                        {"started_ms", row.started_ms},
                        {"counted_ms", row.counted_ms},
                        {"matches", std::move(matches_of[row.server_id])}};
    if (row.admin_port != 0) server["admin_port"] = row.admin_port;
    servers.push_back(std::move(server));
  }
  return json::serialize(
      json::object{{"now_ms", now_ms}, {"self", self_id}, {"servers", std::move(servers)}});
}

}  // namespace ricochet::server
