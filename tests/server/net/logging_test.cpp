#include "logging.h"

#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include <regex>
#include <sstream>
#include <string>

namespace ricochet::server::logging_test {
namespace {

/// A logger writing into a string, as the server's would to stderr.
struct CapturedLog {
  explicit CapturedLog(LogFormat format, LogLevel level = LogLevel::Info)
      : logger(make_logger("test", level, format,
                           std::make_shared<spdlog::sinks::ostream_sink_mt>(stream))) {}
  std::string text() const { return stream.str(); }

  std::ostringstream stream;
  std::shared_ptr<spdlog::logger> logger;
};

const std::string kTime = R"(\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{6}Z)";

TEST(Logging, TextLineHasTimeLevelLoggerAndMessage) {
  CapturedLog log{LogFormat::Text};
  log.logger->info("match {} started", 3);
  EXPECT_TRUE(std::regex_match(log.text(), std::regex{kTime + " info test: match 3 started\n"}))
      << log.text();
}

TEST(Logging, JsonLineIsOneObject) {
  CapturedLog log{LogFormat::Json};
  log.logger->warn("listening on {}", "0.0.0.0:7777");
  EXPECT_TRUE(std::regex_match(
      log.text(), std::regex{"\\{\"time\":\"" + kTime +
                             "\",\"level\":\"warn\",\"logger\":\"test\",\"thread\":\\d+,"
                             "\"message\":\"listening on 0\\.0\\.0\\.0:7777\"\\}\n"}))
      << log.text();
}

TEST(Logging, JsonEscapesQuotesBackslashesControlsAndInvalidUtf8) {
  CapturedLog log{LogFormat::Json};
  log.logger->info("chat: a\"b\\c\nd\te\x01\x7f f\xff g\xc3\xa9 \xed\xa0\x80");
  const std::string text = log.text();
  EXPECT_NE(text.find("\"message\":\"chat: a\\\"b\\\\c\\nd\\te\\u0001\\u007f f\\ufffd g\xc3\xa9 "
                      "\\ufffd\\ufffd\\ufffd\"}\n"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find('\n'), text.size() - 1);  // one line
}

TEST(Logging, TextEscapesControlsSoAMessageCannotForgeALine) {
  CapturedLog log{LogFormat::Text};
  log.logger->info("name=evil\n2026-01-01T00:00:00.000000Z error test: forged\x1b[31m");
  const std::string text = log.text();
  EXPECT_EQ(text.find('\n'), text.size() - 1) << text;
  EXPECT_NE(text.find("name=evil\\n2026-01-01T00:00:00.000000Z error test: forged\\u001b[31m\n"),
            std::string::npos)
      << text;
}

TEST(Logging, LevelFiltersMessages) {
  CapturedLog log{LogFormat::Text, LogLevel::Warn};
  log.logger->info("hidden");
  log.logger->error("shown");
  EXPECT_EQ(log.text().find("hidden"), std::string::npos);
  EXPECT_NE(log.text().find(" error test: shown\n"), std::string::npos) << log.text();
}

TEST(Logging, LevelsMapToSpdlog) {
  EXPECT_EQ(to_spdlog_level(LogLevel::Trace), spdlog::level::trace);
  EXPECT_EQ(to_spdlog_level(LogLevel::Debug), spdlog::level::debug);
  EXPECT_EQ(to_spdlog_level(LogLevel::Info), spdlog::level::info);
  EXPECT_EQ(to_spdlog_level(LogLevel::Warn), spdlog::level::warn);
  EXPECT_EQ(to_spdlog_level(LogLevel::Error), spdlog::level::err);
  EXPECT_EQ(to_spdlog_level(LogLevel::Critical), spdlog::level::critical);
  EXPECT_EQ(to_spdlog_level(LogLevel::Off), spdlog::level::off);
}

TEST(Logging, SetupMakesTheDefaultLogger) {
  const auto previous = spdlog::default_logger();
  const auto logger = setup_logging(LogLevel::Error, LogFormat::Json);
  EXPECT_EQ(spdlog::default_logger(), logger);
  EXPECT_EQ(logger->level(), spdlog::level::err);
  EXPECT_EQ(logger->name(), "ricochet");
  spdlog::set_default_logger(previous);
}

}  // namespace
}  // namespace ricochet::server::logging_test
