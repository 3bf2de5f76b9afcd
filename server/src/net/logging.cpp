#include "logging.h"

#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <ctime>

namespace ricochet::server {
namespace {

void append(spdlog::memory_buf_t& out, std::string_view text) {
  out.append(text.data(), text.data() + text.size());
}

/// Length of the valid UTF-8 sequence at the start of `text`, or 0 when it is not one
/// (overlong forms, surrogates and code points above U+10FFFF are not valid).
std::size_t utf8_sequence_length(std::string_view text) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  const unsigned char lead = byte(0);
  std::size_t length = 0;
  char32_t code_point = 0;
  if (lead < 0x80) return 1;
  if (lead >= 0xc2 && lead <= 0xdf) {
    length = 2;
    code_point = lead & 0x1f;
  } else if (lead >= 0xe0 && lead <= 0xef) {
    length = 3;
    code_point = lead & 0x0f;
  } else if (lead >= 0xf0 && lead <= 0xf4) {
    length = 4;
    code_point = lead & 0x07;
  } else {
    return 0;
  }
  if (text.size() < length) return 0;
  for (std::size_t i = 1; i < length; ++i) {
    if ((byte(i) & 0xc0) != 0x80) return 0;
    code_point = (code_point << 6) | (byte(i) & 0x3f);
  }
  const bool overlong =
      (length == 3 && code_point < 0x800) || (length == 4 && code_point < 0x10000);
  const bool surrogate = code_point >= 0xd800 && code_point <= 0xdfff;
  if (overlong || surrogate || code_point > 0x10ffff) return 0;
  return length;
}

void append_unicode_escape(spdlog::memory_buf_t& out, unsigned code) {
  static constexpr char kHex[] = "0123456789abcdef";
  const char escape[6] = {'\\',
                          'u',
                          kHex[(code >> 12) & 0xf],
                          kHex[(code >> 8) & 0xf],
                          kHex[(code >> 4) & 0xf],
                          kHex[code & 0xf]};
  out.append(escape, escape + 6);
}

/// 2026-12-01T18:41:12.123456Z
void append_time(spdlog::memory_buf_t& out, spdlog::log_clock::time_point time) {
  const auto since_epoch = time.time_since_epoch();
  const auto seconds = std::chrono::floor<std::chrono::seconds>(since_epoch);
  const auto micros =
      std::chrono::duration_cast<std::chrono::microseconds>(since_epoch - seconds).count();
  const std::time_t whole = static_cast<std::time_t>(seconds.count());
  std::tm utc{};
  gmtime_r(&whole, &utc);
  char text[40];
  const std::size_t length = std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%S", &utc);
  append(out, std::string_view{text, length});
  fmt::format_to(std::back_inserter(out), ".{:06d}Z", micros);
}

/// The names of the config's log.level ("warn", not spdlog's "warning").
std::string_view level_text(spdlog::level::level_enum level) {
  switch (level) {
    case spdlog::level::trace:
      return "trace";
    case spdlog::level::debug:
      return "debug";
    case spdlog::level::info:
      return "info";
    case spdlog::level::warn:
      return "warn";
    case spdlog::level::err:
      return "error";
    case spdlog::level::critical:
      return "critical";
    default:
      return "off";
  }
}

}  // namespace

void append_escaped_log_text(std::string_view text, bool json, spdlog::memory_buf_t& out) {
  std::size_t i = 0;
  while (i < text.size()) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c >= 0x80) {
      const std::size_t length = utf8_sequence_length(text.substr(i));
      if (length == 0) {
        append(out, json ? "\\ufffd" : "\xef\xbf\xbd");
        ++i;
      } else {
        append(out, text.substr(i, length));
        i += length;
      }
      continue;
    }
    switch (c) {
      case '\n':
        append(out, "\\n");
        break;
      case '\r':
        append(out, "\\r");
        break;
      case '\t':
        append(out, "\\t");
        break;
      case '"':
      case '\\':
        if (json) out.push_back('\\');
        out.push_back(static_cast<char>(c));
        break;
      default:
        if (c < 0x20 || c == 0x7f) {
          append_unicode_escape(out, c);
        } else {
          out.push_back(static_cast<char>(c));
        }
    }
    ++i;
  }
}

spdlog::level::level_enum to_spdlog_level(LogLevel level) {
  switch (level) {
    case LogLevel::Trace:
      return spdlog::level::trace;
    case LogLevel::Debug:
      return spdlog::level::debug;
    case LogLevel::Info:
      return spdlog::level::info;
    case LogLevel::Warn:
      return spdlog::level::warn;
    case LogLevel::Error:
      return spdlog::level::err;
    case LogLevel::Critical:
      return spdlog::level::critical;
    case LogLevel::Off:
      return spdlog::level::off;
  }
  return spdlog::level::info;
}

void LineFormatter::format(const spdlog::details::log_msg& message, spdlog::memory_buf_t& out) {
  const std::string_view logger{message.logger_name.data(), message.logger_name.size()};
  const std::string_view payload{message.payload.data(), message.payload.size()};
  if (format_ == LogFormat::Json) {
    append(out, "{\"time\":\"");
    append_time(out, message.time);
    append(out, "\",\"level\":\"");
    append(out, level_text(message.level));
    append(out, "\",\"logger\":\"");
    append_escaped_log_text(logger, true, out);
    fmt::format_to(std::back_inserter(out), "\",\"thread\":{},\"message\":\"", message.thread_id);
    append_escaped_log_text(payload, true, out);
    append(out, "\"}\n");
    return;
  }
  append_time(out, message.time);
  out.push_back(' ');
  append(out, level_text(message.level));
  out.push_back(' ');
  append_escaped_log_text(logger, false, out);
  append(out, ": ");
  append_escaped_log_text(payload, false, out);
  out.push_back('\n');
}

std::unique_ptr<spdlog::formatter> LineFormatter::clone() const {
  return std::make_unique<LineFormatter>(format_);
}

std::shared_ptr<spdlog::logger> make_logger(std::string name, LogLevel level, LogFormat format,
                                            spdlog::sink_ptr sink) {
  auto logger = std::make_shared<spdlog::logger>(std::move(name), std::move(sink));
  logger->set_formatter(std::make_unique<LineFormatter>(format));
  logger->set_level(to_spdlog_level(level));
  logger->flush_on(spdlog::level::warn);
  return logger;
}

std::shared_ptr<spdlog::logger> setup_logging(LogLevel level, LogFormat format) {
  auto logger =
      make_logger("ricochet", level, format, std::make_shared<spdlog::sinks::stderr_sink_mt>());
  spdlog::set_default_logger(logger);
  return logger;
}

}  // namespace ricochet::server
