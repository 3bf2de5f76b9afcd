#pragma once
/// What every bench shares: a stopwatch, the figures of a set of samples (ricochet/stats:
/// nearest-rank percentiles), and its results as one JSON line each, printed and appended to a
/// results file (tools/bench/results/<bench>.jsonl when given as --out).

#include <chrono>
#include <concepts>
#include <cstdint>
#include <fstream>
#include <string>
#include <string_view>

#include "ricochet/stats/percentile.h"
#include "ricochet/stats/summary.h"

namespace ricochet::bench {

/// Wall time on the steady clock since construction or the last restart().
class Stopwatch {
 public:
  Stopwatch() : start_(Clock::now()) {}
  void restart() { start_ = Clock::now(); }
  double elapsed_s() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }
  double elapsed_ms() const { return elapsed_s() * 1e3; }
  double elapsed_us() const { return elapsed_s() * 1e6; }

 private:
  using Clock = std::chrono::steady_clock;
  Clock::time_point start_;
};

/// The steady clock, ns: wall time.
std::int64_t steady_ns();
/// This thread's CPU time, ns: what a thread costs on a machine shared with other work.
std::int64_t thread_cpu_ns();

/// One JSON object on one line, its fields in the order added. Keys are written as given (the
/// benches' own names); text values are escaped.
class JsonObject {
 public:
  JsonObject& text(std::string_view key, std::string_view value);
  JsonObject& flag(std::string_view key, bool value);
  template <std::integral T>
  requires(!std::same_as<T, bool>) JsonObject& integer(std::string_view key, T value) {
    return raw(key, std::to_string(value));
  }
  /// Fixed notation with `decimals` digits after the point (printf "%.Nf").
  JsonObject& number(std::string_view key, double value, int decimals);
  /// The shortest of fixed and exponent notation (printf "%g"), for options such as seconds.
  JsonObject& general(std::string_view key, double value);
  JsonObject& object(std::string_view key, const JsonObject& value);
  /// The object's text, braces included, no newline.
  std::string str() const { return "{" + fields_ + "}"; }

 private:
  JsonObject& raw(std::string_view key, std::string_view value);
  std::string fields_;
};

/// The line of one result: a JsonObject whose first field is "bench":name.
JsonObject result_line(std::string_view bench);

/// Where a bench's lines go: stdout, and appended to a file when one is given.
class ResultsOut {
 public:
  /// path: the file to append to; empty for stdout only.
  explicit ResultsOut(const std::string& path);
  /// False when a path was given and cannot be opened for appending.
  bool ok() const { return path_.empty() || file_.is_open(); }
  const std::string& path() const { return path_; }
  /// Prints the line and appends it to the file, each with a newline.
  void write(const JsonObject& line);

 private:
  std::string path_;
  std::ofstream file_;
};

}  // namespace ricochet::bench
