// libFuzzer target for `ricochet-loadtest merge`'s reader of a generator's report.json
// (tools/loadtest/include/ricochet/loadtest/merge.h): files from other machines, untrusted.
// Nothing may crash; a read is deterministic; a refusal names the file; an accepted report's
// steps keep their counts in range.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <variant>

#include "fuzz_check.h"
#include "ricochet/loadtest/merge.h"

namespace {

using namespace ricochet::loadtest;

using ricochet::fuzz::check;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const auto first = read_generator_report(text, "fuzz/report.json");
  const auto second = read_generator_report(text, "fuzz/report.json");
  check(first.index() == second.index());
  if (const auto* error = std::get_if<std::string>(&first)) {
    check(error->rfind("fuzz/report.json", 0) == 0);
    check(*error == std::get<std::string>(second));
    return 0;
  }
  const GeneratorReport& report = std::get<GeneratorReport>(first);
  check(report.steps.size() == std::get<GeneratorReport>(second).steps.size());
  for (const StepSummary& step : report.steps) {
    check(step.bots >= 0 && step.bots_connected >= 0);
  }
  return 0;
}
