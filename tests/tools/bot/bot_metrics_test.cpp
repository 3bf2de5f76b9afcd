#include "ricochet/bot/bot_metrics.h"

#include <gtest/gtest.h>

namespace ricochet::bot::bot_metrics_test {
namespace {

TEST(SnapshotGapCounter, CountsTheSnapshotsMissingBetweenTwoAtTheSnapshotInterval) {
  SnapshotGapCounter every_tick(1.0);
  for (const std::uint32_t tick : {10u, 11u, 12u, 15u, 16u}) every_tick.on_snapshot(tick);
  EXPECT_EQ(every_tick.received(), 5u);
  EXPECT_EQ(every_tick.lost(), 2u);  // 13 and 14

  SnapshotGapCounter every_third(3.0);  // 60 Hz ticks, 20 Hz snapshots
  for (const std::uint32_t tick : {3u, 6u, 9u, 18u}) every_third.on_snapshot(tick);
  EXPECT_EQ(every_third.lost(), 2u);  // 12 and 15
}

TEST(BotMetrics, RatesArePerSecondOfConnectionAndTheJsonIsOneLine) {
  BotMetrics metrics;
  proto::TransportCounters counters;
  counters.packets_in = 600;
  counters.bytes_in = 60000;
  metrics.add_transport(counters, 10.0);
  metrics.snapshots = 590;
  metrics.snapshots_lost = 10;
  metrics.server_packets = 1000;
  metrics.server_packets_missing = 20;
  metrics.rtt_ms = {1, 2, 3, 100};
  const std::string json = metrics.to_json();
  EXPECT_EQ(json.find('\n'), std::string::npos);
  EXPECT_NE(json.find("\"packets_in_per_s\":60.00"), std::string::npos) << json;
  EXPECT_NE(json.find("\"bytes_in_per_s\":6000.0"), std::string::npos) << json;
  EXPECT_NE(json.find("\"snapshot_loss\":0.01667"), std::string::npos) << json;
  EXPECT_NE(json.find("\"packet_loss\":0.02000"), std::string::npos) << json;
  EXPECT_NE(json.find("\"rtt_ms_p99\":100.000"), std::string::npos) << json;
  EXPECT_NE(json.find("\"rtt_ms_p50\":2.000"), std::string::npos) << json;

  BotMetrics total;
  total.merge(metrics);
  total.merge(metrics);
  EXPECT_EQ(total.packets_in, 1200u);
  EXPECT_EQ(total.server_packets_missing, 40u);
  EXPECT_EQ(total.rtt_ms.size(), 8u);
}

}  // namespace
}  // namespace ricochet::bot::bot_metrics_test
