#pragma once
/// What a load test leaves in its directory: report.json (the summary of every step, the last
/// at the top level), steps.jsonl (one line per step, for results/*.jsonl), the series as gnuplot
/// data files, plots.gp and the PNGs gnuplot draws from it.

#include <string>

#include "ricochet/loadtest/load_run.h"

namespace ricochet::loadtest {

struct ReportContext {
  std::string command;          ///< the command line, for the record
  std::string measured_at_utc;  ///< "2026-12-02T07:40:00Z"
};

/// Writes report.json and the data files into config.out (created); empty on success, else
/// what could not be written.
std::string write_report(const LoadRun& run, const LoadTestConfig& config,
                         const ReportContext& context);

/// Writes plots.gp and runs gnuplot on it in config.out; empty on success, else why the PNGs
/// are missing (gnuplot not installed: tools/deps.sh installs gnuplot-nox).
std::string draw_plots(const LoadRun& run, const LoadTestConfig& config);

}  // namespace ricochet::loadtest
