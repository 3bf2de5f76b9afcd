// --fleet's reader of GET /fleet (fleet_directory.h): every row one server as if listed by
// --server, the answering server first, pinned to its row's certificate, a row without an admin
// port kept with port 0; anything else refused with its reason counted and the field named.

#include "ricochet/loadtest/fleet_directory.h"

#include <gtest/gtest.h>

#include <string>

#include "enum_count.h"

namespace ricochet::loadtest::fleet_directory_test {
namespace {

const std::string kHash(64, 'a');

std::string row(const std::string& id, bool self, const std::string& host, int control,
                const std::string& admin) {
  return R"({"server_id":")" + id + R"(","self":)" + (self ? "true" : "false") + R"(,"host":")" +
         host + R"(","control_port":)" + std::to_string(control) +
         R"(,"game_port":7778,"admin_port":)" + admin + R"(,"certificate_sha256":")" + kHash +
         R"(","version":"0.9","capacity":64,"players":3,"heartbeat_age_ms":12,)" +
         R"("started_ms":1,"counted_ms":2,"matches":[]})";
}

std::string fleet(const std::string& rows) {
  return R"({"now_ms":5,"self":"rs-b","servers":[)" + rows + "]}";
}

TEST(FleetDirectory, EveryRowIsAServerTheAnsweringOneFirst) {
  const auto read = parse_fleet(fleet(row("rs-a", false, "127.0.0.1", 7777, "9100") + "," +
                                      row("rs-b", true, "127.0.0.1", 7787, "9110") + "," +
                                      row("rs-c", false, "10.0.0.7", 7777, "null")));
  ASSERT_TRUE(std::holds_alternative<std::vector<ServerEndpoint>>(read))
      << std::get<FleetError>(read).message;
  const auto& servers = std::get<std::vector<ServerEndpoint>>(read);
  ASSERT_EQ(servers.size(), 3u);
  EXPECT_EQ(servers[0].label(), "127.0.0.1:7787");  // self
  EXPECT_EQ(servers[0].admin_port, 9110);
  EXPECT_EQ(servers[1].label(), "127.0.0.1:7777");
  EXPECT_EQ(servers[1].admin_port, 9100);
  EXPECT_EQ(servers[2].label(), "10.0.0.7:7777");
  EXPECT_EQ(servers[2].admin_port, 0);  // not advertised: played on, never scraped
  EXPECT_EQ(servers[0].fingerprint.size(), 95u) << servers[0].fingerprint;  // AA:.. 32 pairs
  EXPECT_TRUE(servers[0].trust_file.empty());
  LoadTestConfig config;
  config.servers = servers;
  EXPECT_EQ(config.validate(), "");
}

TEST(FleetDirectory, AnythingElseIsRefusedWithItsReasonCounted) {
  const std::string good = row("rs-a", true, "127.0.0.1", 7777, "9100");
  const std::vector<std::pair<std::string, FleetRefusal>> refused = {
      {"", FleetRefusal::NotJson},
      {"{\"servers\":[", FleetRefusal::NotJson},
      {std::string(100, '[') + std::string(100, ']'), FleetRefusal::NotJson},
      {"[]", FleetRefusal::NotAFleet},
      {R"({"servers":{}})", FleetRefusal::NotAFleet},
      {fleet(""), FleetRefusal::NoServers},
      {fleet("7"), FleetRefusal::BadServer},
      {fleet(row("", true, "127.0.0.1", 7777, "9100")), FleetRefusal::BadServer},
      {fleet(row(std::string(65, 'x'), true, "127.0.0.1", 7777, "9100")), FleetRefusal::BadServer},
      {fleet(row("rs-a", true, "127.0.0.1", 0, "9100")), FleetRefusal::BadServer},
      {fleet(row("rs-a", true, "127.0.0.1", 65536, "9100")), FleetRefusal::BadServer},
      {fleet(row("rs-a", true, "127.0.0.1", 7777, "\"9100\"")), FleetRefusal::BadServer},
      {fleet(row("rs-a", true, "127.0.0.1", 7777, "-1")), FleetRefusal::BadServer},
      {fleet(row("rs-a", true, "game1.example.net", 7777, "9100")), FleetRefusal::HostNotIpv4},
      {fleet(good + "," + good), FleetRefusal::Duplicate},
  };
  FleetReader reader;
  for (const auto& [body, reason] : refused) {
    const auto read = reader.read(body);
    ASSERT_TRUE(std::holds_alternative<FleetError>(read)) << body;
    EXPECT_EQ(name(std::get<FleetError>(read).reason), std::string(name(reason))) << body;
    EXPECT_FALSE(std::get<FleetError>(read).message.empty());
  }
  EXPECT_EQ(reader.refused(FleetRefusal::NotJson), 3u);
  EXPECT_EQ(reader.refused(FleetRefusal::BadServer), 7u);
  EXPECT_EQ(reader.refused(FleetRefusal::HostNotIpv4), 1u);

  // The field is named, with what came.
  const auto bad_port = parse_fleet(fleet(row("rs-a", true, "127.0.0.1", 65536, "9100")));
  EXPECT_NE(std::get<FleetError>(bad_port).message.find("control_port must be an integer 1..65535"
                                                        ", got 65536"),
            std::string::npos)
      << std::get<FleetError>(bad_port).message;

  std::string many;
  for (std::size_t i = 0; i <= kMaxServers; ++i) {
    if (i > 0) many += ',';
    many += row("rs-" + std::to_string(i), false, "127.0.0.1", static_cast<int>(7000 + i), "null");
  }
  EXPECT_EQ(std::get<FleetError>(parse_fleet(fleet(many))).reason, FleetRefusal::TooManyServers);
}

TEST(FleetDirectory, TheSourceIsANumericAddressAndAnAdminPort) {
  const auto source = parse_fleet_source("127.0.0.1:9100");
  ASSERT_TRUE(std::holds_alternative<ServerEndpoint>(source));
  EXPECT_EQ(std::get<ServerEndpoint>(source).admin_port, 9100);
  for (const char* bad : {"", "127.0.0.1", "127.0.0.1:", "127.0.0.1:0", "host:9100", "1.2.3:9"}) {
    EXPECT_TRUE(std::holds_alternative<std::string>(parse_fleet_source(bad))) << bad;
  }
}

TEST(FleetDirectory, RefusalsAreACountedEnum) {
  ricochet::test::expect_counted<FleetRefusal>(kFleetRefusalCount,
                                               [](FleetRefusal r) { return name(r); });
}

}  // namespace
}  // namespace ricochet::loadtest::fleet_directory_test
