// The network simulator (link_simulator.h) with fixed seeds: loss, delays, duplication and
// reordering happen at the rates and within the bounds configured, and the same seed gives the
// same deliveries.
#include "ricochet/bot/link_simulator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace ricochet::bot::link_simulator_test {
namespace {

constexpr int kPackets = 20000;
constexpr proto::TimeUs kSpacingUs = 16'667;  // one datagram per 60 Hz tick

LinkConfig link(double latency_ms, double jitter_ms, double loss = 0, double duplicate = 0,
                double reorder = 0) {
  LinkConfig config;
  config.latency_ms = latency_ms;
  config.jitter_ms = jitter_ms;
  config.loss = loss;
  config.duplicate = duplicate;
  config.reorder = reorder;
  return config;
}

struct Delivery {
  std::uint32_t index = 0;  ///< the datagram's send order
  proto::TimeUs sent = 0;
  proto::TimeUs at = 0;
};

/// Sends kPackets datagrams numbered by their first 4 bytes and collects what comes out, polling
/// every 1 ms.
std::vector<Delivery> run(const LinkConfig& config, std::uint64_t seed,
                          LinkCounters* counters = nullptr) {
  LinkSimulator link(config, seed);
  std::vector<Delivery> out;
  std::vector<std::uint8_t> datagram;
  const proto::TimeUs end = kPackets * kSpacingUs + 10'000'000;
  int sent = 0;
  for (proto::TimeUs now = 0; now <= end; now += 1000) {
    while (sent < kPackets && sent * kSpacingUs <= now) {
      const auto k = static_cast<std::uint32_t>(sent++);
      link.send({std::uint8_t(k), std::uint8_t(k >> 8), std::uint8_t(k >> 16), 0}, now);
    }
    while (link.poll(now, datagram)) {
      const std::uint32_t k = datagram[0] | (datagram[1] << 8) | (datagram[2] << 16);
      out.push_back({k, static_cast<proto::TimeUs>(k) * kSpacingUs, now});
    }
  }
  EXPECT_EQ(link.in_flight(), 0u);
  if (counters) *counters = link.counters();
  return out;
}

TEST(LinkSimulator, APerfectLinkIsInactive) {
  EXPECT_FALSE(LinkConfig{}.active());
  EXPECT_TRUE(link(1, 0).active());
}

TEST(LinkSimulator, LosesAtTheRateGiven) {
  LinkCounters counters;
  const auto delivered = run(link(0, 0, 0.2), 7, &counters);
  // Binomial(20000, 0.2): standard deviation 57; 4000 +- 300 is over five of them.
  EXPECT_NEAR(static_cast<double>(counters.dropped), 4000, 300);
  EXPECT_EQ(delivered.size(), kPackets - counters.dropped);
  EXPECT_EQ(counters.sent, static_cast<std::uint64_t>(kPackets));
}

TEST(LinkSimulator, DelaysWithinLatencyPlusMinusJitter) {
  const auto delivered = run(link(150, 50), 11);
  ASSERT_EQ(delivered.size(), static_cast<std::size_t>(kPackets));
  double sum_ms = 0;
  proto::TimeUs low = INT64_MAX, high = 0;
  int overtaken = 0;
  for (std::size_t i = 0; i < delivered.size(); ++i) {
    const proto::TimeUs delay = delivered[i].at - delivered[i].sent;
    low = std::min(low, delay);
    high = std::max(high, delay);
    sum_ms += static_cast<double>(delay) / 1000;
    if (i > 0 && delivered[i].index < delivered[i - 1].index) ++overtaken;
  }
  // Polled every ms: a delivery comes at most 1 ms after it is due.
  EXPECT_GE(low, 100'000);
  EXPECT_LE(high, 201'000);
  EXPECT_LT(low, 102'000);  // the whole range is used
  EXPECT_GT(high, 198'000);
  EXPECT_NEAR(sum_ms / kPackets, 150.5, 1.5);  // uniform: the mean is the latency
  EXPECT_GT(overtaken, kPackets / 10);         // +-50 ms against 16.7 ms spacing reorders plenty
}

TEST(LinkSimulator, DuplicatesAtTheRateGiven) {
  LinkCounters counters;
  const auto delivered = run(link(20, 5, 0, 0.1), 3, &counters);
  EXPECT_NEAR(static_cast<double>(counters.duplicated), 2000, 200);  // sd 42
  EXPECT_EQ(delivered.size(), kPackets + counters.duplicated);
  std::vector<int> copies(kPackets, 0);
  for (const Delivery& d : delivered) ++copies[d.index];
  int twice = 0;
  for (const int c : copies) {
    ASSERT_TRUE(c == 1 || c == 2);
    twice += c == 2;
  }
  EXPECT_EQ(static_cast<std::uint64_t>(twice), counters.duplicated);
}

TEST(LinkSimulator, ReordersAtTheRateGiven) {
  LinkCounters counters;
  const auto delivered = run(link(30, 0, 0, 0, 0.05), 5, &counters);
  EXPECT_NEAR(static_cast<double>(counters.reordered), 1000, 130);  // sd 31
  // Without jitter only the held ones come late: each arrives 20 ms late, after the one sent
  // next (16.7 ms later), so one out-of-order arrival per held datagram.
  int out_of_order = 0;
  for (std::size_t i = 1; i < delivered.size(); ++i) {
    if (delivered[i].index < delivered[i - 1].index) ++out_of_order;
  }
  EXPECT_NEAR(out_of_order, static_cast<double>(counters.reordered), counters.reordered * 0.1);
  for (const Delivery& d : delivered) {
    const proto::TimeUs delay = d.at - d.sent;
    EXPECT_TRUE((delay >= 30'000 && delay <= 31'000) || (delay >= 50'000 && delay <= 51'000))
        << delay;
  }
}

TEST(LinkSimulator, TheSameSeedGivesTheSameDeliveries) {
  const LinkConfig config = link(80, 30, 0.1, 0.05, 0.05);
  const auto a = run(config, 99);
  const auto b = run(config, 99);
  const auto c = run(config, 100);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].index, b[i].index);
    ASSERT_EQ(a[i].at, b[i].at);
  }
  bool differs = a.size() != c.size();
  for (std::size_t i = 0; !differs && i < a.size(); ++i) differs = a[i].at != c[i].at;
  EXPECT_TRUE(differs);
}

TEST(LinkConfig, ValidatesEveryField) {
  EXPECT_EQ(LinkConfig{}.validate(), "");
  EXPECT_EQ(link(-1, 0).validate(), "sim latency_ms must be 0..5000, got -1.000000");
  EXPECT_NE(link(10, 20).validate().find("sim jitter_ms must be 0..latency_ms"), std::string::npos);
  EXPECT_NE(link(0, 0, std::nan("")).validate().find("sim loss must be 0..1"), std::string::npos);
  EXPECT_NE(link(0, 0, 0, 2).validate().find("sim duplicate"), std::string::npos);
  EXPECT_NE(link(0, 0, 0, 0, -0.5).validate().find("sim reorder"), std::string::npos);
}

}  // namespace
}  // namespace ricochet::bot::link_simulator_test
