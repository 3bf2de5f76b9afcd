// The [dashboard] keys (config.h, DashboardConfig): each in its range, and max_replays at least
// replay_workers. (A file of its own: in config_test.cpp's unity batch it tipped GCC 12 into a
// false -Warray-bounds in admin_http_test.cpp.)

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "ricochet/server/config.h"

namespace ricochet::server::dashboard_config_test {
namespace {

TEST(DashboardConfig, ReplayBoundsAreValidatedByKeyAndTogether) {
  ServerConfig config;
  EXPECT_TRUE(config.validate().empty());
  EXPECT_TRUE(apply_config_toml("[dashboard]\nreplay_workers = 2\nmax_replays = 3\n"
                                "replay_memory_mb = 64\n",
                                "test.toml", config)
                  .empty());
  EXPECT_EQ(config.dashboard.replay_workers, 2);
  EXPECT_EQ(config.dashboard.max_replays, 3);
  EXPECT_EQ(config.dashboard.replay_memory_mb, 64);
  config.dashboard.max_replays = 1;
  EXPECT_EQ(config.validate(),
            std::vector<std::string>{
                "dashboard.max_replays must be at least dashboard.replay_workers (2), got 1"});
  ServerConfig wrong;
  ASSERT_TRUE(
      apply_config_toml("[dashboard]\nreplay_workers = 9\nmax_replays = 65\nreplay_memory_mb = 8\n",
                        "test.toml", wrong)
          .empty());
  const auto problems = wrong.validate();
  ASSERT_EQ(problems.size(), 3u);
  EXPECT_NE(problems[0].find("dashboard.replay_workers must be 1..8, got 9"), std::string::npos)
      << problems[0];
  EXPECT_NE(problems[1].find("dashboard.max_replays must be 1..64, got 65"), std::string::npos)
      << problems[1];
  EXPECT_NE(problems[2].find("dashboard.replay_memory_mb must be 16..65536, got 8"),
            std::string::npos)
      << problems[2];
}

}  // namespace
}  // namespace ricochet::server::dashboard_config_test
