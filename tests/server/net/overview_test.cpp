#include "overview.h"

#include <gtest/gtest.h>

#include <string>

namespace ricochet::server::overview_test {
namespace {

OverviewMatch match(std::uint32_t id, std::string name, double p50_ms) {
  OverviewMatch m;
  m.id = id;
  m.name = std::move(name);
  m.map = "arena";
  m.mode = "ffa";
  m.phase = "running";
  m.seated = 2;
  m.connected = 1;
  m.max_players = 8;
  m.tick_p50_ms = p50_ms;
  m.tick_p99_ms = 2 * p50_ms;
  return m;
}

TEST(Overview, EachMatchKeepsItsLastTickTimesAndBandwidthIsPerSecond) {
  Overview overview{2};
  OverviewSample sample;
  sample.matches = {match(1, "ffa-1", 0.5), match(2, "say \"hi\"\n", 1)};
  sample.matches[0].leader = "ann";
  sample.matches[0].leader_score = 3;
  sample.matches[0].time_left_s = 61.5;
  sample.players = 3;
  sample.bytes_in = 1000;
  sample.bytes_out = 5000;
  sample.db_queue_depth = 4;
  sample.fleet = true;
  sample.refusals = {
      {"game", "bad_size", 0}, {"control", "rate_limited", 7}, {"input", "stale", 12, true}};
  EXPECT_EQ(overview.update(10'000'000, sample),
            R"({"at_s":0.000,"server":{"players":3,"matches":2,"bytes_in_per_s":0.000,)"
            R"("bytes_out_per_s":0.000,"db_queue_depth":4,"fleet":true},"matches":[)"
            R"({"id":1,"name":"ffa-1","map":"arena","mode":"ffa","phase":"running","seated":2,)"
            R"("connected":1,"max_players":8,"leader":"ann","leader_score":3,"time_left_s":61.500,)"
            R"("overruns":0,"tick_p50_ms":[0.500],"tick_p99_ms":[1.000]},)"
            R"({"id":2,"name":"say \"hi\"\u000a","map":"arena","mode":"ffa","phase":"running",)"
            R"("seated":2,"connected":1,"max_players":8,"leader":null,"leader_score":0,)"
            R"("time_left_s":null,"overruns":0,"tick_p50_ms":[1.000],"tick_p99_ms":[2.000]}],)"
            R"("refusals":[{"channel":"control","reason":"rate_limited","count":7},)"
            R"({"channel":"input","reason":"stale","count":12,"expected":true}]})");

  // Half a second later: 500 bytes in is 1000 B/s; three samples of match 1, two kept; match 2
  // ended, a match 3 began.
  sample.matches = {match(1, "ffa-1", 0.25), match(3, "ffa-3", 0.125)};
  sample.bytes_in = 1500;
  sample.bytes_out = 6000;
  overview.update(10'500'000, sample);
  sample.matches[0].tick_p50_ms = 0.75;
  sample.bytes_in = 1600;
  const std::string json = overview.update(11'000'000, sample);
  EXPECT_NE(json.find(R"("at_s":1.000,"server":{"players":3,"matches":2,"bytes_in_per_s":200.000,)"
                      R"("bytes_out_per_s":0.000)"),
            std::string::npos)
      << json;
  EXPECT_NE(json.find(R"("id":1,"name":"ffa-1")"), std::string::npos) << json;
  EXPECT_NE(json.find(R"("tick_p50_ms":[0.250,0.750],"tick_p99_ms":[0.500,0.500])"),
            std::string::npos)
      << json;
  EXPECT_NE(json.find(R"("tick_p50_ms":[0.125,0.125])"), std::string::npos) << json;
  EXPECT_EQ(json.find(R"("id":2)"), std::string::npos) << json;
}

}  // namespace
}  // namespace ricochet::server::overview_test
