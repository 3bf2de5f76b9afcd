// libFuzzer target for the load-test tool's reader of the server's /metrics text (Prometheus
// exposition format), which it reads from the network: any bytes. Nothing may crash; a parse is
// deterministic; every sample accepted has a name and at most kMaxLabels labels, and never more
// samples than lines.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>
#include <variant>
#include <vector>

#include "fuzz_check.h"
#include "ricochet/loadtest/prometheus_text.h"

namespace {

using namespace ricochet::loadtest;

using ricochet::fuzz::check;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const auto first = parse_prometheus_text(text);
  const auto second = parse_prometheus_text(text);
  check(first.index() == second.index());
  if (const auto* error = std::get_if<std::string>(&first)) {
    check(!error->empty());
    check(*error == std::get<std::string>(second));
    return 0;
  }
  const auto& samples = std::get<std::vector<MetricSample>>(first);
  const auto& again = std::get<std::vector<MetricSample>>(second);
  check(samples.size() == again.size());
  const std::size_t lines =
      static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')) + 1;
  check(samples.size() <= lines);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    check(!samples[i].name.empty());
    check(samples[i].labels.size() <= kMaxLabels);
    check(samples[i].name == again[i].name && samples[i].labels == again[i].labels);
  }
  return 0;
}
