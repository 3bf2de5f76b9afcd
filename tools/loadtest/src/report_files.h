#pragma once
/// What the load test's two reports (report.cpp: steps; soak_report.cpp: the soak) write the same
/// way: text files, the errors table, and gnuplot run on a script of PNGs.

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "ricochet/loadtest/error_kinds.h"

namespace ricochet::loadtest {

/// Writes `text` to `path`; false with `error` set when it cannot.
bool write_file(const std::filesystem::path& path, const std::string& text, std::string& error);

/// errors.dat: "kind count" per kind seen (a "none 0" row when there is none, so the plot has a
/// bar to draw).
std::string errors_table(const ErrorCounts& errors);

/// `ms` sorted, one "ms fraction" line each (the fraction of values at or below it), under
/// `header`: a distribution to draw with steps ("0 0" when empty).
std::string distribution_table(std::vector<double> ms, const char* header);

/// {"name":percent,...} with three decimals (a value that is not finite as 0).
std::string percent_object_json(const std::map<std::string, double>& percent);

/// The first lines of every plots.gp: PNGs of 960×600, a grid, time on x.
extern const char* const kGnuplotPreamble;

/// The lines that start a PNG in a gnuplot script: its file, title and y label.
std::string gnuplot_png(const char* file, const char* title, const char* ylabel);

/// Writes `script` to DIR/plots.gp and runs gnuplot on it in DIR (its output in
/// DIR/gnuplot.log); empty when the PNGs were drawn, otherwise what went wrong.
std::string run_gnuplot(const std::filesystem::path& dir, const std::string& script);

}  // namespace ricochet::loadtest
