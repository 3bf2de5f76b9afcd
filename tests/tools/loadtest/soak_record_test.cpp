#include "ricochet/loadtest/soak_record.h"

#include <gtest/gtest.h>

#include <vector>

namespace ricochet::loadtest::soak_record_test {
namespace {

constexpr FlatnessBounds kBounds{16.0, 10.0};

/// `seconds` samples a second apart: 10 bots playing, 60 snapshots a second each with 1 in 10
/// lost after the warm-up, RSS and fds flat, the database growing 0.01 MiB a sample.
std::vector<SoakSample> run(int seconds) {
  std::vector<SoakSample> out;
  double snapshots = 0;
  double lost = 0;
  for (int s = 0; s < seconds; ++s) {
    SoakSample sample;
    sample.t_s = s;
    sample.server_ok = true;
    sample.playing = 10;
    sample.tick_p99_ms = 1.0 + (s % 3);  // 1, 2, 3
    sample.tick_max_ms = 5;
    sample.rss_mib = 100;
    sample.open_fds = 50;
    sample.db_mib = 1 + 0.01 * s;
    snapshots += 600;
    lost += s >= 60 ? 60 : 300;  // a bad start
    sample.snapshots = snapshots;
    sample.snapshots_lost = lost;
    sample.server_packets = 700.0 * (s + 1);
    sample.server_packets_missing = 140.0 * (s + 1);  // 20 %
    sample.sign_ins = static_cast<std::uint64_t>(10 + s / 10);
    sample.matches_finished = static_cast<std::uint64_t>(s / 60);
    out.push_back(sample);
  }
  return out;
}

TEST(SoakSummary, SummarisesTheSamplesAfterTheWarmUp) {
  std::vector<SoakSample> samples = run(600);
  samples[300].tick_max_ms = 40;  // one slow tick
  const SoakSummary s = summarise_soak(samples, 60, kBounds);
  EXPECT_EQ(s.samples, 600);
  EXPECT_EQ(s.duration_s, 599);
  EXPECT_TRUE(s.flatness.flat()) << s.flatness.verdict();
  EXPECT_EQ(s.flatness.samples, 540);
  EXPECT_EQ(s.rss_mib_first, 100);
  EXPECT_EQ(s.fds_max, 50);
  EXPECT_DOUBLE_EQ(s.db_mib_first, 1);
  EXPECT_DOUBLE_EQ(s.db_mib_last, 1 + 0.01 * 599);
  ASSERT_TRUE(s.db_mib_per_hour);
  EXPECT_NEAR(*s.db_mib_per_hour, 36, 1e-6);  // 0.01 MiB a second
  EXPECT_EQ(s.tick_p99_ms_median, 2);
  EXPECT_EQ(s.tick_p99_ms_max, 3);
  EXPECT_EQ(s.tick_max_ms_max, 40);
  EXPECT_NEAR(s.snapshot_loss, 60.0 / 660, 1e-9);  // the bad start is in the warm-up
  EXPECT_NEAR(s.packet_loss, 0.2, 1e-9);
  EXPECT_EQ(s.playing_min, 10);
  EXPECT_EQ(s.sign_ins, 69u);
  EXPECT_EQ(s.matches_finished, 9u);
}

TEST(SoakSummary, AFailedReadIsLeftOutNotTakenAsZero) {
  std::vector<SoakSample> samples = run(600);
  for (int s = 100; s < 600; s += 50) {
    samples[s].server_ok = false;
    samples[s].open_fds = -1;  // a failed scrape reads nothing
    samples[s].tick_p99_ms = 0;
  }
  const SoakSummary s = summarise_soak(samples, 60, kBounds);
  EXPECT_EQ(s.scrapes_failed, 10);
  EXPECT_TRUE(s.flatness.flat()) << s.flatness.verdict();
  EXPECT_EQ(s.flatness.samples, 530);
}

TEST(SoakSummary, AGrowingServerIsNotFlat) {
  std::vector<SoakSample> samples = run(3600);
  for (SoakSample& sample : samples) sample.rss_mib += sample.t_s / 3600 * 40;  // 40 MiB/h
  const SoakSummary s = summarise_soak(samples, 360, kBounds);
  EXPECT_FALSE(s.flatness.flat());
  EXPECT_NEAR(*s.flatness.rss_mib_per_hour, 40, 1e-6);
}

TEST(SoakSummary, NoSamplesGiveAnEmptySummaryThatIsNotFlat) {
  const SoakSummary s = summarise_soak({}, 60, kBounds);
  EXPECT_EQ(s.samples, 0);
  EXPECT_FALSE(s.flatness.flat());
}

}  // namespace
}  // namespace ricochet::loadtest::soak_record_test
