#include "harness.h"

#include <time.h>

#include <cstdio>

#include "ricochet/tools/json_text.h"

namespace ricochet::bench {

std::int64_t steady_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

std::int64_t thread_cpu_ns() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<std::int64_t>(now.tv_sec) * 1'000'000'000 + now.tv_nsec;
}

JsonObject& JsonObject::raw(std::string_view key, std::string_view value) {
  if (!fields_.empty()) fields_ += ',';
  fields_ += tools::json_string(key);
  fields_ += ':';
  fields_ += value;
  return *this;
}

JsonObject& JsonObject::text(std::string_view key, std::string_view value) {
  return raw(key, tools::json_string(value));
}

JsonObject& JsonObject::flag(std::string_view key, bool value) {
  return raw(key, value ? "true" : "false");
}

JsonObject& JsonObject::number(std::string_view key, double value, int decimals) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  return raw(key, text);
}

JsonObject& JsonObject::general(std::string_view key, double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%g", value);
  return raw(key, text);
}

JsonObject& JsonObject::object(std::string_view key, const JsonObject& value) {
  return raw(key, value.str());
}

JsonObject result_line(std::string_view bench) {
  return JsonObject().text("bench", bench);
}

ResultsOut::ResultsOut(const std::string& path) : path_(path) {
  if (!path_.empty()) file_.open(path_, std::ios::app);
}

void ResultsOut::write(const JsonObject& line) {
  const std::string text = line.str();
  std::printf("%s\n", text.c_str());
  std::fflush(stdout);
  if (file_.is_open()) file_ << text << '\n' << std::flush;
}

}  // namespace ricochet::bench
