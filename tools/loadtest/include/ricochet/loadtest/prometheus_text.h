#pragma once
/// A reader of the Prometheus text exposition format (what the server's /metrics answers):
/// untrusted text, every line checked, the first bad line named.

#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

namespace ricochet::loadtest {

struct MetricSample {
  std::string name;
  std::vector<std::pair<std::string, std::string>> labels;  ///< as written, unescaped
  double value = 0;

  /// The value of label `key`; empty when absent.
  std::string_view label(std::string_view key) const;
};

inline constexpr std::size_t kMaxMetricsBytes = 32u << 20;  ///< 32 MiB
inline constexpr std::size_t kMaxLabels = 16;               ///< per sample

/// The samples of `text` (comments and blank lines skipped), or why it is not exposition text
/// ("line 12: expected '=' after label name, got ...").
std::variant<std::vector<MetricSample>, std::string> parse_prometheus_text(std::string_view text);

}  // namespace ricochet::loadtest
