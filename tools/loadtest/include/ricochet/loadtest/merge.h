#pragma once
/// `ricochet-loadtest merge OUT DIR...`: the reports of generator processes run at the same time
/// (one per machine, each with its own --name) against the same servers, merged into one.
///
/// Step i of every generator makes merged step i. Bots, their connections, snapshot counts,
/// bandwidth, errors and bots placed per server are summed; latency percentiles (RTT, connect
/// time, placement time) are the nearest rank
/// of the union of every generator's samples (report.json keeps them per step), never a mean of
/// percentiles; each server's figures are taken once, from the first generator (in the order
/// given) that scraped it in that step, and the step's server figures are totalled from those
/// (StepSummary::total_servers); the generators' own CPU and RSS are each one's, the step's the
/// largest. A server is known by its label, so every generator must name it the same way.
///
/// Every report.json is untrusted: read with bounded size and depth, every field used checked
/// for type and range; a bad one is named with the field ("DIR/report.json: steps[1].bots: ...")
/// and refused, or skipped and listed with skip_bad.

#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "ricochet/loadtest/report.h"
#include "ricochet/loadtest/run_record.h"

namespace ricochet::loadtest {

/// The largest report.json merge reads.
inline constexpr std::size_t kMaxReportBytes = 256u << 20;

/// One generator's report.json.
struct GeneratorReport {
  std::string source;  ///< the file it came from
  std::string measured_at_utc;
  std::string command;
  std::vector<StepSummary> steps;
};

/// Reads report.json `text`; on failure why, starting with `source`.
std::variant<GeneratorReport, std::string> read_generator_report(std::string_view text,
                                                                 const std::string& source);

struct MergedReport {
  std::vector<GeneratorReport> generators;
  std::vector<std::pair<std::string, std::string>> skipped;  ///< source, why
  std::vector<StepSummary> steps;
};

/// Merges generators' reports step by step; refuses (why) none, or different step counts.
std::variant<MergedReport, std::string> merge_reports(std::vector<GeneratorReport> generators);

/// Reads DIR/report.json of every directory and merges them; a bad report refuses the whole
/// merge, or with `skip_bad` is left out and named in `skipped`.
std::variant<MergedReport, std::string> merge_directories(const std::vector<std::string>& dirs,
                                                          bool skip_bad);

/// Writes OUT/report.json (the merged steps, the last at the top level, the generators and any
/// skipped report), the data files and, with `plots`, the PNGs; empty on success, else why not.
std::string write_merged_report(const MergedReport& merged, const std::string& out, bool plots,
                                const ReportContext& context);

}  // namespace ricochet::loadtest
