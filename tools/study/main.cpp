/// physics-study: the accuracy ↔ speed study of the physics engine.
///
///   physics-study run --out DIR [--quick | --smoke] [--scene NAME ...]
///       runs the scenes in this build's precision; writes DIR/results-<precision>.csv and
///       DIR/series-<precision>.csv
///   physics-study report --out DIR --results A.csv [B.csv] --series A.csv [B.csv] [--mode M]
///                        [--revision R]
///       merges runs into DIR/results.csv and DIR/series.csv, writes DIR/report.md and the
///       gnuplot scripts DIR/gnuplot/*.gp (run gnuplot in DIR to draw DIR/*.png)
///   physics-study list
///       prints the scene names
///
/// tools/physics-study drives all of it for the float and double builds.

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "report.h"
#include "results_io.h"
#include "scenes.h"
#include "study.h"

namespace study = ricochet::study;

namespace {

int run(const std::string& out_dir, study::Mode mode, const std::vector<std::string>& names) {
  std::vector<const study::Scene*> selected;
  for (const std::string& name : names) {
    const study::Scene* scene = study::find_scene(name);
    if (!scene) {
      std::fprintf(stderr, "physics-study: unknown scene '%s' (see physics-study list)\n",
                   name.c_str());
      return 2;
    }
    selected.push_back(scene);
  }
  if (selected.empty()) {
    for (const study::Scene& s : study::scenes()) selected.push_back(&s);
  }
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) {
    std::fprintf(stderr, "physics-study: cannot create %s: %s\n", out_dir.c_str(),
                 ec.message().c_str());
    return 2;
  }
  study::Study s(mode);
  for (const study::Scene* scene : selected) {
    const auto start = std::chrono::steady_clock::now();
    const std::size_t rows_before = s.rows().size();
    scene->run(s);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(stderr, "physics-study (%s): %-14s %4zu rows  %6.1f s\n", study::precision_name(),
                 scene->name, s.rows().size() - rows_before, seconds);
  }
  const std::string suffix = std::string("-") + study::precision_name() + ".csv";
  const bool ok = study::write_results(out_dir + "/results" + suffix, s.rows()) &&
                  study::write_series(out_dir + "/series" + suffix, s.series());
  return ok ? 0 : 1;
}

/// Concatenates CSV files that share `header` into one. Reads everything first, so the output
/// may be one of the inputs (re-rendering a report from a merged results.csv).
bool merge(const std::vector<std::string>& inputs, const std::string& output, const char* header) {
  std::vector<std::string> lines;
  for (const std::string& input : inputs) {
    std::ifstream in(input);
    std::string line;
    if (!in || !std::getline(in, line) || line != header) {
      std::fprintf(stderr, "physics-study: %s is missing or has another header\n", input.c_str());
      return false;
    }
    while (std::getline(in, line)) {
      if (!line.empty()) lines.push_back(line);
    }
  }
  std::ofstream out(output);
  out << header << '\n';
  for (const std::string& line : lines) out << line << '\n';
  return static_cast<bool>(out);
}

int report(const std::string& out_dir, const std::vector<std::string>& results,
           const std::vector<std::string>& series, const std::string& mode,
           const std::string& revision) {
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  const std::string results_path = out_dir + "/results.csv";
  const std::string series_path = out_dir + "/series.csv";
  if (!merge(results, results_path, study::kResultsHeader) ||
      !merge(series, series_path, study::kSeriesHeader)) {
    return 1;
  }
  study::Results merged;
  std::string problem;
  if (!merged.read_results(results_path, problem) || !merged.read_series(series_path, problem)) {
    std::fprintf(stderr, "physics-study: %s\n", problem.c_str());
    return 1;
  }
  return study::write_report(out_dir, merged, mode, revision) ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Physics accuracy <-> speed study (see tools/physics-study)"};
  app.require_subcommand(1);

  std::string out_dir;
  bool quick = false, smoke = false;
  std::vector<std::string> scene_names;
  CLI::App* run_cmd = app.add_subcommand("run", "run the scenes in this build's precision");
  run_cmd->add_option("--out", out_dir, "directory for results-<precision>.csv")->required();
  auto* quick_flag = run_cmd->add_flag("--quick", quick, "shorter runs, fewer points");
  run_cmd->add_flag("--smoke", smoke, "one or two settings per scene (tests)")
      ->excludes(quick_flag);
  run_cmd->add_option("--scene", scene_names, "run only these scenes (repeatable)");

  std::vector<std::string> results, series;
  std::string mode = "full";
  std::string revision = "unknown";
  CLI::App* report_cmd = app.add_subcommand("report", "merge runs, write report.md and plots");
  report_cmd->add_option("--out", out_dir, "directory for results.csv, report.md, gnuplot/")
      ->required();
  report_cmd->add_option("--results", results, "results-<precision>.csv files")->required();
  report_cmd->add_option("--series", series, "series-<precision>.csv files")->required();
  report_cmd->add_option("--mode", mode, "how the runs were made, for the report's header")
      ->check(CLI::IsMember({"full", "quick", "smoke"}));
  report_cmd->add_option("--revision", revision, "engine revision, for the report's header");

  CLI::App* list_cmd = app.add_subcommand("list", "print the scene names");

  CLI11_PARSE(app, argc, argv);

  if (*run_cmd) {
    const study::Mode m = smoke   ? study::Mode::Smoke
                          : quick ? study::Mode::Quick
                                  : study::Mode::Full;
    return run(out_dir, m, scene_names);
  }
  if (*report_cmd) return report(out_dir, results, series, mode, revision);
  if (*list_cmd) {
    for (const study::Scene& s : study::scenes()) std::printf("%s\n", s.name);
  }
  return 0;
}
