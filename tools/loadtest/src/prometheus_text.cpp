#include "ricochet/loadtest/prometheus_text.h"

#include <cctype>
#include <cmath>
#include <cstdlib>

namespace ricochet::loadtest {

std::string_view MetricSample::label(std::string_view key) const {
  for (const auto& [name, value] : labels) {
    if (name == key) return value;
  }
  return {};
}

namespace {

bool name_start(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || c == ':';
}
bool name_char(char c) {
  return name_start(c) || (c >= '0' && c <= '9');
}

/// Reads one line; on failure `error` says what.
class LineReader {
 public:
  explicit LineReader(std::string_view line) : line_(line) {}

  bool read(MetricSample& out, std::string& error) {
    if (!read_name(out.name)) return fail(error, "expected a metric name");
    if (at('{') && !read_labels(out, error)) return false;
    if (!at(' ') && !at('\t')) return fail(error, "expected a space before the value");
    while (at(' ') || at('\t')) ++pos_;
    const std::size_t start = pos_;
    while (pos_ < line_.size() && line_[pos_] != ' ' && line_[pos_] != '\t') ++pos_;
    if (!read_value(line_.substr(start, pos_ - start), out.value)) {
      return fail(error, "expected a number (or +Inf, -Inf, NaN) as the value");
    }
    // An optional timestamp (integer ms) may follow; it is ignored.
    while (at(' ') || at('\t')) ++pos_;
    while (pos_ < line_.size() &&
           (std::isdigit(static_cast<unsigned char>(line_[pos_])) || line_[pos_] == '-')) {
      ++pos_;
    }
    while (at(' ') || at('\t')) ++pos_;
    if (pos_ != line_.size()) return fail(error, "unexpected text after the value");
    return true;
  }

 private:
  bool at(char c) const { return pos_ < line_.size() && line_[pos_] == c; }

  bool fail(std::string& error, const char* what) const {
    error = std::string(what) + " at column " + std::to_string(pos_ + 1);
    return false;
  }

  bool read_name(std::string& out) {
    if (pos_ >= line_.size() || !name_start(line_[pos_])) return false;
    const std::size_t start = pos_;
    while (pos_ < line_.size() && name_char(line_[pos_])) ++pos_;
    out.assign(line_.substr(start, pos_ - start));
    return true;
  }

  bool read_labels(MetricSample& out, std::string& error) {
    ++pos_;  // '{'
    while (!at('}')) {
      if (out.labels.size() >= kMaxLabels) return fail(error, "more than 16 labels");
      std::string key;
      if (!read_name(key)) return fail(error, "expected a label name");
      if (!at('=')) return fail(error, "expected '=' after the label name");
      ++pos_;
      if (!at('"')) return fail(error, "expected '\"' opening the label value");
      ++pos_;
      std::string value;
      while (!at('"')) {
        if (pos_ >= line_.size()) return fail(error, "unterminated label value");
        char c = line_[pos_++];
        if (c == '\\') {
          if (pos_ >= line_.size()) return fail(error, "unterminated escape");
          const char escaped = line_[pos_++];
          if (escaped == 'n') {
            c = '\n';
          } else if (escaped == '\\' || escaped == '"') {
            c = escaped;
          } else {
            return fail(error, "unknown escape in a label value");
          }
        }
        value += c;
      }
      ++pos_;  // '"'
      out.labels.emplace_back(std::move(key), std::move(value));
      if (at(',')) {
        ++pos_;
      } else if (!at('}')) {
        return fail(error, "expected ',' or '}' after a label");
      }
    }
    ++pos_;  // '}'
    return true;
  }

  static bool read_value(std::string_view text, double& out) {
    if (text == "+Inf" || text == "Inf") {
      out = HUGE_VAL;
      return true;
    }
    if (text == "-Inf") {
      out = -HUGE_VAL;
      return true;
    }
    if (text == "NaN") {
      out = std::nan("");
      return true;
    }
    if (text.empty() || text.size() > 64) return false;
    const std::string copy(text);
    char* end = nullptr;
    out = std::strtod(copy.c_str(), &end);
    return end == copy.c_str() + copy.size() && std::isfinite(out);
  }

  std::string_view line_;
  std::size_t pos_ = 0;
};

}  // namespace

std::variant<std::vector<MetricSample>, std::string> parse_prometheus_text(std::string_view text) {
  if (text.size() > kMaxMetricsBytes) {
    return "metrics text of " + std::to_string(text.size()) + " bytes, at most " +
           std::to_string(kMaxMetricsBytes) + " accepted";
  }
  std::vector<MetricSample> samples;
  std::size_t line_number = 0;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(start, end - start);
    start = end + 1;
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.empty() || line.front() == '#') continue;
    MetricSample sample;
    std::string error;
    if (!LineReader(line).read(sample, error)) {
      return "line " + std::to_string(line_number) + ": " + error;
    }
    samples.push_back(std::move(sample));
  }
  return samples;
}

}  // namespace ricochet::loadtest
