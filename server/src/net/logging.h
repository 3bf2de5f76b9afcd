#pragma once
/// The server's logs through spdlog: one line per message on stderr, as text or as JSON lines.
///
/// Text:  2026-12-01T18:41:12.123456Z info ricochet: match 3 started
/// JSON:
/// {"time":"2026-12-01T18:41:12.123456Z","level":"info","logger":"ricochet","thread":4242,"message":"match
/// 3 started"}
///
/// Messages often carry untrusted text (usernames, chat, addresses), so a message can never
/// forge a line: in both formats control characters are escaped (\n, \t, \u001b...) and bytes
/// that are not UTF-8 become U+FFFD; JSON also escapes '"' and '\'. Times are UTC, microseconds.

#include <spdlog/formatter.h>
#include <spdlog/logger.h>

#include <memory>
#include <string>
#include <string_view>

#include "ricochet/server/config.h"

namespace ricochet::server {

spdlog::level::level_enum to_spdlog_level(LogLevel level);

/// Formats one message as one line in `format`.
class LineFormatter final : public spdlog::formatter {
 public:
  explicit LineFormatter(LogFormat format) : format_(format) {}
  void format(const spdlog::details::log_msg& message, spdlog::memory_buf_t& out) override;
  std::unique_ptr<spdlog::formatter> clone() const override;

 private:
  LogFormat format_;
};

/// A logger named `name` writing to `sink` at `level` and above in `format`.
std::shared_ptr<spdlog::logger> make_logger(std::string name, LogLevel level, LogFormat format,
                                            spdlog::sink_ptr sink);

/// Makes the process logger "ricochet" on stderr and makes it spdlog's default, so
/// spdlog::info(...) anywhere writes through it; flushes at warn and above. Call once at start,
/// before other threads log.
std::shared_ptr<spdlog::logger> setup_logging(LogLevel level, LogFormat format);

/// Appends `text` escaped for a log line: JSON string content when `json`, else text with only
/// control characters and invalid UTF-8 replaced.
void append_escaped_log_text(std::string_view text, bool json, spdlog::memory_buf_t& out);

}  // namespace ricochet::server
