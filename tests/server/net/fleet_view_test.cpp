// GET /fleet's JSON (fleet_view.h) on fake time: every live row with its matches, this server
// marked self, heartbeat ages from the given clock, no admin port as null, a match of a server
// not among the rows left out, and text that needs escaping escaped.

#include "fleet_view.h"

#include <gtest/gtest.h>

#include <boost/json.hpp>

namespace ricochet::server::test::fleet_view_test {
namespace {

namespace json = boost::json;

db::GameServerRow row(const std::string& id, db::UnixMillis heartbeat_ms, std::int32_t admin) {
  db::GameServerRow r;
  r.server_id = id;
  r.host = id + ".example.net";
  r.control_port = 7777;
  r.game_port = 7778;
  r.admin_port = admin;
  r.certificate_sha256 = std::string(64, 'a');
  r.version = "ricochet \"1.0\"";
  r.capacity = 64;
  r.players = 5;
  r.heartbeat_ms = heartbeat_ms;
  r.started_ms = 1'000;
  r.counted_ms = heartbeat_ms - 3;
  return r;
}

TEST(FleetView, ListsEveryRowWithItsMatchesAndMarksThisServer) {
  constexpr db::UnixMillis kNow = 1'700'000'000'000;
  db::FleetDirectory directory;
  directory.servers = {row("a", kNow - 840, 9100), row("b", kNow + 20, 0)};
  directory.matches = {{"a", db::HostedMatch{1, "ffa", "foundry", 3, 16, true}},
                       {"a", db::HostedMatch{2, "tdm", "arena", 16, 16, false}},
                       {"gone", db::HostedMatch{7, "ffa", "foundry", 1, 16, true}}};
  const json::value fleet = json::parse(fleet_json(directory, "b", kNow));

  EXPECT_EQ(fleet.at("now_ms").as_int64(), kNow);
  EXPECT_EQ(fleet.at("self").as_string(), "b");
  const json::array& servers = fleet.at("servers").as_array();
  ASSERT_EQ(servers.size(), 2u);
  const json::object& a = servers[0].as_object();
  EXPECT_EQ(a.at("server_id").as_string(), "a");
  EXPECT_FALSE(a.at("self").as_bool());
  EXPECT_EQ(a.at("host").as_string(), "a.example.net");
  EXPECT_EQ(a.at("control_port").as_int64(), 7777);
  EXPECT_EQ(a.at("game_port").as_int64(), 7778);
  EXPECT_EQ(a.at("admin_port").as_int64(), 9100);
  EXPECT_EQ(a.at("certificate_sha256").as_string(), std::string(64, 'a'));
  EXPECT_EQ(a.at("version").as_string(), "ricochet \"1.0\"");
  EXPECT_EQ(a.at("capacity").as_int64(), 64);
  EXPECT_EQ(a.at("players").as_int64(), 5);
  EXPECT_EQ(a.at("heartbeat_age_ms").as_int64(), 840);
  EXPECT_EQ(a.at("started_ms").as_int64(), 1'000);
  EXPECT_EQ(a.at("counted_ms").as_int64(), kNow - 843);
  const json::array& matches = a.at("matches").as_array();
  ASSERT_EQ(matches.size(), 2u);
  EXPECT_EQ(matches[1].at("match_id").as_int64(), 2);
  EXPECT_EQ(matches[1].at("mode").as_string(), "tdm");
  EXPECT_EQ(matches[1].at("map").as_string(), "arena");
  EXPECT_EQ(matches[1].at("players").as_int64(), 16);
  EXPECT_EQ(matches[1].at("capacity").as_int64(), 16);
  EXPECT_FALSE(matches[1].at("open").as_bool());

  const json::object& b = servers[1].as_object();
  EXPECT_TRUE(b.at("self").as_bool());
  EXPECT_TRUE(b.at("admin_port").is_null());            // not advertised
  EXPECT_EQ(b.at("heartbeat_age_ms").as_int64(), -20);  // its clock is ahead of this one
  EXPECT_TRUE(b.at("matches").as_array().empty());
}

TEST(FleetView, AnEmptyDirectoryIsAnEmptyList) {
  const json::value fleet = json::parse(fleet_json({}, "rs-1", 5));
  EXPECT_TRUE(fleet.at("servers").as_array().empty());
  EXPECT_EQ(fleet.at("self").as_string(), "rs-1");
}

}  // namespace
}  // namespace ricochet::server::test::fleet_view_test
