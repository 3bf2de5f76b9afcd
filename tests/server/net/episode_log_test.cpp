#include "episode_log.h"

#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <sstream>

namespace ricochet::server::episode_log_test {
namespace {

constexpr proto::TimeUs kSecond = proto::kMicrosPerSecond;

/// Captures the default logger's lines for the test's lifetime.
class EpisodeLogTest : public ::testing::Test {
 protected:
  void SetUp() override {
    previous_ = spdlog::default_logger();
    auto logger = std::make_shared<spdlog::logger>(
        "episodes", std::make_shared<spdlog::sinks::ostream_sink_mt>(lines_));
    logger->set_pattern("%v");
    spdlog::set_default_logger(logger);
  }
  void TearDown() override { spdlog::set_default_logger(previous_); }
  int logged() const {
    const std::string text = lines_.str();
    return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
  }

  std::ostringstream lines_;
  std::shared_ptr<spdlog::logger> previous_;
};

TEST_F(EpisodeLogTest, AFloodIsLoggedWhenItStartsAndWhenItEnds) {
  EpisodeLog log(10 * kSecond);
  EXPECT_TRUE(log.refuse("chat_flood", "account 7", "21 lines in 1 s", 0));
  for (int i = 1; i <= 1000; ++i) EXPECT_FALSE(log.refuse("chat_flood", "account 7", "", i * 1000));
  EXPECT_EQ(logged(), 1);
  EXPECT_NE(lines_.str().find("chat_flood from account 7: 21 lines in 1 s"), std::string::npos);

  EXPECT_EQ(log.open_episodes(1 * kSecond), 1u);
  EXPECT_EQ(log.open_episodes(12 * kSecond), 0u);  // quiet for 10 s: over, and its end logged
  EXPECT_EQ(logged(), 2);
  EXPECT_NE(lines_.str().find("episode ended, 1001 refusals in 1.0 s"), std::string::npos);
  EXPECT_TRUE(log.refuse("chat_flood", "account 7", "again", 13 * kSecond));
}

TEST_F(EpisodeLogTest, ReasonsAndKeysAreSeparateEpisodes) {
  EpisodeLog log(10 * kSecond);
  EXPECT_TRUE(log.refuse("chat_flood", "account 7", "", 0));
  EXPECT_TRUE(log.refuse("chat_flood", "account 8", "", 0));
  EXPECT_TRUE(log.refuse("half_open_cap", "account 7", "", 0));
  EXPECT_EQ(log.open_episodes(0), 3u);
}

TEST_F(EpisodeLogTest, ManyKeysShareOneEpisodeSoMemoryStaysBounded) {
  EpisodeLog log(10 * kSecond, 4);
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(log.refuse("address_flood", std::to_string(i), "", 0));
  EXPECT_TRUE(log.refuse("address_flood", "spoofed 1", "", 1));
  for (int i = 2; i < 10000; ++i)
    log.refuse("address_flood", "spoofed " + std::to_string(i), "", i);
  EXPECT_EQ(log.open_episodes(10000), 5u);
  EXPECT_EQ(logged(), 5);
}

}  // namespace
}  // namespace ricochet::server::episode_log_test
