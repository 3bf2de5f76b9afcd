#pragma once
/// What a soak leaves in its directory: report.json (the options, the summary and the flatness
/// verdict with its slopes and bounds), soak.dat (the series), errors.dat, plots.gp and the PNGs
/// gnuplot draws from it.

#include <string>

#include "ricochet/loadtest/report.h"
#include "ricochet/loadtest/soak_config.h"
#include "ricochet/loadtest/soak_record.h"
#include "ricochet/loadtest/soak_run.h"

namespace ricochet::loadtest {

/// Writes report.json, soak.dat and errors.dat into config.out; empty on success, else what
/// could not be written.
std::string write_soak_report(const SoakRun& run, const SoakSummary& summary,
                              const LoadTestConfig& config, const SoakConfig& soak,
                              const ReportContext& context);

/// Writes plots.gp and runs gnuplot on it in config.out (rss_fds.png, db.png, tick_p99.png,
/// snapshot_loss.png, bots.png, cpu.png, errors.png); empty on success, else why the PNGs are
/// missing.
std::string draw_soak_plots(const SoakSummary& summary, const LoadTestConfig& config);

}  // namespace ricochet::loadtest
