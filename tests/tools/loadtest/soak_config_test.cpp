#include "ricochet/loadtest/soak_config.h"

#include <gtest/gtest.h>

namespace ricochet::loadtest::soak_config_test {
namespace {

LoadTestConfig hour_run() {
  LoadTestConfig run;
  run.bots = 40;
  run.bots_per_address = 2;
  run.duration_s = 3600;
  return run;
}

TEST(SoakConfig, TheDefaultsAreTheIssuesLinkAndValidForAnHour) {
  const SoakConfig soak;
  EXPECT_EQ(soak.link.latency_ms, 200);
  EXPECT_EQ(soak.link.jitter_ms, 50);
  EXPECT_EQ(soak.link.loss, 0.2);
  EXPECT_EQ(soak.link.duplicate, 0.05);
  EXPECT_EQ(soak.link.reorder, 0.05);
  EXPECT_EQ(soak.validate(hour_run()), "");
  EXPECT_EQ(soak.warmup_for(3600), 360);  // 10 %
  EXPECT_EQ(soak.warmup_for(120), 60);    // at least a minute
}

TEST(SoakConfig, RegistrationsStayUnderTheServersDefaultPerAddress) {
  ChurnConfig churn;  // lives 60..600 s (330 s on average), 10 % new accounts
  EXPECT_NEAR(churn.registrations_in_an_hour(2, 3600), 2 * (1 + 0.1 * 3600 / 330), 1e-9);
  EXPECT_NEAR(churn.registrations_in_an_hour(2, 7200), 2 * (1 + 0.1 * 3600 / 330), 1e-9);
  EXPECT_NEAR(churn.registrations_in_an_hour(2, 120), 2 * (1 + 0.1 * 120 / 330), 1e-9);
  SoakConfig soak;
  LoadTestConfig run = hour_run();
  run.bots_per_address = 8;  // the load test's default: 8 * 2.09 accounts an hour
  EXPECT_NE(soak.validate(run).find("register about"), std::string::npos) << soak.validate(run);
}

TEST(SoakConfig, RefusesWhatIsOutOfRangeNamingIt) {
  SoakConfig soak;
  soak.link.jitter_ms = 300;  // more than the latency
  EXPECT_NE(soak.validate(hour_run()).find("jitter_ms"), std::string::npos);
  soak = {};
  soak.churn.min_life_s = 700;
  EXPECT_NE(soak.validate(hour_run()).find("churn min life"), std::string::npos);
  soak = {};
  soak.warmup_s = 3600;
  EXPECT_NE(soak.validate(hour_run()).find("warm-up"), std::string::npos);
  soak = {};
  soak.bounds.fds_per_hour = 0;
  EXPECT_NE(soak.validate(hour_run()).find("bounds"), std::string::npos);
  soak = {};
  LoadTestConfig sweep = hour_run();
  sweep.sweep = {10, 20};
  EXPECT_NE(soak.validate(sweep).find("sweep"), std::string::npos);
}

TEST(SoakConfig, NoChurnIsAllowed) {
  SoakConfig soak;
  soak.churn.max_life_s = 0;
  EXPECT_EQ(soak.validate(hour_run()), "");
  EXPECT_EQ(soak.churn.registrations_in_an_hour(2, 3600), 2);
}

}  // namespace
}  // namespace ricochet::loadtest::soak_config_test
