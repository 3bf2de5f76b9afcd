#include "ricochet/loadtest/merge.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <variant>

namespace ricochet::loadtest::merge_test {
namespace {

namespace fs = std::filesystem;

ServerWindow server(const std::string& label, double cpu_percent, int players) {
  ServerWindow out;
  out.label = label;
  out.scraped = true;
  out.matches = 1;
  out.players = players;
  out.tick = {0.2, 0.3, 0.5, 0.9};
  out.tick_p99_mean_ms = 0.5;
  out.overruns = 1;
  out.cpu_percent = cpu_percent;
  out.rss_mb = 30;
  out.packets_in_per_s = 100;
  out.phase_percent["total"] = cpu_percent / 2;
  return out;
}

/// One generator's step: `bots` all connected, `rtt` its pooled RTT samples.
StepSummary step(int bots, std::vector<double> rtt, std::vector<ServerWindow> servers) {
  StepSummary out;
  out.bots = bots;
  out.bots_connected = bots;
  out.measured_s = 10;
  out.snapshots_received = 600.0 * bots;
  out.snapshots_lost = 6.0 * bots;
  out.snapshots_per_s_per_bot = 60;
  out.kbps_in_total = 50.0 * bots;
  out.kbps_out_total = 60.0 * bots;
  out.kbps_in_per_client = 50;
  out.kbps_out_per_client = 60;
  out.generator_cpu_percent = bots / 10.0;
  out.rtt_ms_samples = std::move(rtt);
  out.connect_ms_samples = {100, 200};
  out.errors["connect_failed"] = 2;
  out.servers = std::move(servers);
  out.total_servers();
  return out;
}

/// report.json as a generator writes it (report.cpp: the steps with their samples).
std::string report_text(const std::vector<StepSummary>& steps) {
  std::string out =
      R"({"tool":"ricochet-loadtest","measured_at_utc":"2026-12-06T16:00:00Z","command":"x",)"
      R"("steps":[)";
  for (std::size_t i = 0; i < steps.size(); ++i) {
    if (i > 0) out += ',';
    out += steps[i].to_json(/*samples=*/true);
  }
  return out + "]," + steps.back().to_json().substr(1);
}

GeneratorReport read_ok(const std::string& text, const std::string& source) {
  auto read = read_generator_report(text, source);
  if (const auto* error = std::get_if<std::string>(&read)) ADD_FAILURE() << *error;
  return std::holds_alternative<GeneratorReport>(read) ? std::get<GeneratorReport>(read)
                                                       : GeneratorReport{};
}

std::string read_error(const std::string& text) {
  auto read = read_generator_report(text, "g/report.json");
  return std::holds_alternative<std::string>(read) ? std::get<std::string>(read) : "";
}

TEST(Merge, SumsBotsBandwidthAndErrorsAndTakesEachServerOnce) {
  // Both generators scraped both servers; their figures of one server differ a little (scraped
  // at other moments) and must not be added up.
  const auto a =
      read_ok(report_text({step(30, {1, 2, 3}, {server("s1:1", 40, 24), server("s2:1", 20, 24)})}),
              "a/report.json");
  const auto b =
      read_ok(report_text({step(18, {4, 5}, {server("s1:1", 41, 24), server("s2:1", 21, 24)})}),
              "b/report.json");
  auto merged = merge_reports({a, b});
  ASSERT_TRUE(std::holds_alternative<MergedReport>(merged)) << std::get<std::string>(merged);
  const StepSummary& m = std::get<MergedReport>(merged).steps.at(0);
  EXPECT_EQ(m.bots, 48);
  EXPECT_EQ(m.bots_connected, 48);
  EXPECT_DOUBLE_EQ(m.kbps_in_total, 50.0 * 48);
  EXPECT_DOUBLE_EQ(m.kbps_in_per_client, 50);
  EXPECT_DOUBLE_EQ(m.snapshot_loss, 6.0 / 606.0);
  EXPECT_EQ(m.errors.at("connect_failed"), 4u);
  EXPECT_DOUBLE_EQ(m.generator_cpu_percent, 3.0);  // the busier generator's
  ASSERT_EQ(m.servers.size(), 2u);
  EXPECT_EQ(m.servers[0].label, "s1:1");
  EXPECT_DOUBLE_EQ(m.servers[0].cpu_percent, 40);  // from the first generator, once
  EXPECT_DOUBLE_EQ(m.servers_cpu_percent_total, 60);
  EXPECT_DOUBLE_EQ(m.server_cpu_percent, 40);  // the busiest server's
  EXPECT_STREQ(m.server_cpu_source, "metrics");
  EXPECT_EQ(m.matches, 2);
  EXPECT_DOUBLE_EQ(m.overruns, 2);
  EXPECT_DOUBLE_EQ(m.server_phase_percent.at("total"), 30);
  EXPECT_EQ(m.connect_ms_samples.size(), 4u);
}

TEST(Merge, PlacedBotsAreSummedPerServerAndPlacementTimesPooled) {
  ServerWindow b_server = server("b:1", 30, 12);
  b_server.placement_tickets = {{"assigned", 14}, {"no_server_available", 1}};
  StepSummary one = step(8, {1}, {server("a:1", 10, 0), b_server});
  one.bots_placed = {{"b:1", 5}, {"c:1", 3}};
  one.placement_ms_samples = {10, 20, 30};
  StepSummary two = step(4, {1}, {server("a:1", 11, 0), server("b:1", 31, 12)});
  two.bots_placed = {{"c:1", 4}};
  two.placement_ms_samples = {500};
  auto merged = merge_reports({read_ok(report_text({one}), "a"), read_ok(report_text({two}), "b")});
  ASSERT_TRUE(std::holds_alternative<MergedReport>(merged)) << std::get<std::string>(merged);
  const StepSummary& m = std::get<MergedReport>(merged).steps.at(0);
  EXPECT_EQ(m.bots_placed, (std::map<std::string, int>{{"b:1", 5}, {"c:1", 7}}));
  EXPECT_EQ(m.placement_ms_samples.size(), 4u);
  EXPECT_EQ(m.placement_ms_p50, 20.0);
  EXPECT_EQ(m.placement_ms_max, 500.0);
  // Each server's tickets once, from the first generator that scraped it.
  ASSERT_EQ(m.servers.size(), 2u);
  EXPECT_EQ(m.servers[1].placement_tickets,
            (std::map<std::string, double>{{"assigned", 14}, {"no_server_available", 1}}));
}

TEST(Merge, LatencyPercentilesAreOfTheUnionNotAMeanOfPercentiles) {
  // A's bots see 1 ms; B's see 1 ms but for two samples of 100 ms: B's p99 alone is 100 ms, the
  // mean of the two p99s 50.5 ms, the union's p99 (rank 198 of 200) 1 ms.
  std::vector<double> quiet(100, 1.0);
  std::vector<double> spiky(98, 1.0);
  spiky.push_back(100);
  spiky.push_back(100);
  const auto a = read_ok(report_text({step(10, quiet, {})}), "a");
  const auto b = read_ok(report_text({step(10, spiky, {})}), "b");
  auto merged = merge_reports({a, b});
  ASSERT_TRUE(std::holds_alternative<MergedReport>(merged));
  const StepSummary& m = std::get<MergedReport>(merged).steps.at(0);
  EXPECT_EQ(m.rtt_ms_samples.size(), 200u);
  EXPECT_EQ(m.rtt_ms_p99, 1.0);
  EXPECT_EQ(m.rtt_ms_p50, 1.0);
  EXPECT_EQ(m.connect_ms_max, 200.0);
  // The samples survive report.json at the precision written (%.5g).
  EXPECT_EQ(read_ok(report_text({step(1, {12.345, 0.25}, {})}), "c").steps[0].rtt_ms_samples,
            (std::vector<double>{12.345, 0.25}));
}

TEST(Merge, RefusesBadReportsNamingTheFileAndTheField) {
  const std::string good = report_text({step(4, {1}, {server("s1:1", 10, 4)})});
  EXPECT_EQ(read_error(good), "");
  EXPECT_NE(read_error(good.substr(0, good.size() / 2)).find("g/report.json: not JSON"),
            std::string::npos);
  EXPECT_EQ(read_error("[1]"), "g/report.json: expected a JSON object");
  std::string bad_bots = good;
  bad_bots.replace(bad_bots.find("\"bots\":4"), 8, "\"bots\":\"4\"");
  EXPECT_EQ(read_error(bad_bots),
            "g/report.json: steps[0].bots: expected a number 0..1e+09, got \"4\"");
  std::string negative = good;
  negative.replace(negative.find("\"rtt_ms_samples\":[1"), 19, "\"rtt_ms_samples\":[-1");
  EXPECT_EQ(read_error(negative),
            "g/report.json: steps[0].rtt_ms_samples: expected numbers >= 0, got -1");
  std::string server_cpu = good;
  server_cpu.replace(server_cpu.find("\"cpu_percent\":10"), 16, "\"cpu_percent\":1e99");
  EXPECT_NE(read_error(server_cpu).find("steps[0].servers[0].cpu_percent: expected a number"),
            std::string::npos)
      << read_error(server_cpu);
  std::string old = good;  // written before the samples were kept
  old.replace(old.find("\"rtt_ms_samples\""), 16, "\"rtt_ms_samplez\"");
  EXPECT_EQ(read_error(old), "g/report.json: steps[0].rtt_ms_samples: expected an array");
  EXPECT_EQ(read_error(R"({"tool":"ricochet-loadtest","mode":"soak"})"),
            "g/report.json: a soak's report, not a load test's");
  EXPECT_EQ(read_error(R"({"tool":"other","steps":[]})"),
            "g/report.json: not a ricochet-loadtest report (\"tool\")");
  EXPECT_EQ(read_error(std::string(100, '[') + std::string(100, ']')).substr(0, 23),
            "g/report.json: not JSON");
  std::string connected = good;
  connected.replace(connected.find("\"bots_connected\":4"), 18, "\"bots_connected\":5");
  EXPECT_EQ(read_error(connected), "g/report.json: steps[0]: bots_connected 5 > bots 4");
  // Generators that ran different sweeps do not merge.
  const auto one = read_ok(good, "a");
  const auto two = read_ok(report_text({step(4, {1}, {}), step(8, {1}, {})}), "b");
  auto merged = merge_reports({one, two});
  ASSERT_TRUE(std::holds_alternative<std::string>(merged));
  EXPECT_NE(std::get<std::string>(merged).find("a has 1, b 2"), std::string::npos);
}

TEST(Merge, ADirectoryWithABadReportIsRefusedOrSkipped) {
  const fs::path root =
      fs::temp_directory_path() / ("ricochet-merge-test-" + std::to_string(getpid()));
  fs::create_directories(root / "good");
  fs::create_directories(root / "cut");
  fs::create_directories(root / "empty");
  const std::string good = report_text({step(4, {1}, {server("s1:1", 10, 4)})});
  std::ofstream(root / "good" / "report.json") << good;
  std::ofstream(root / "cut" / "report.json") << good.substr(0, 100);  // a killed writer's
  const std::vector<std::string> dirs = {(root / "good").string(), (root / "cut").string(),
                                         (root / "empty").string()};
  auto refused = merge_directories(dirs, /*skip_bad=*/false);
  ASSERT_TRUE(std::holds_alternative<std::string>(refused));
  EXPECT_NE(
      std::get<std::string>(refused).find((root / "cut" / "report.json").string() + ": not JSON"),
      std::string::npos)
      << std::get<std::string>(refused);
  auto skipped = merge_directories(dirs, /*skip_bad=*/true);
  ASSERT_TRUE(std::holds_alternative<MergedReport>(skipped)) << std::get<std::string>(skipped);
  const MergedReport& merged = std::get<MergedReport>(skipped);
  EXPECT_EQ(merged.generators.size(), 1u);
  ASSERT_EQ(merged.skipped.size(), 2u);
  EXPECT_NE(merged.skipped[1].second.find("cannot read"), std::string::npos);
  EXPECT_EQ(merged.steps.at(0).bots, 4);
  fs::remove_all(root);
}

}  // namespace
}  // namespace ricochet::loadtest::merge_test
