#pragma once
/// report.md and its plots: markdown tables, gnuplot scripts (one per plot, data inline), and the
/// table shapes every scene uses (one knob at a time around the base, two-knob grids).

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "results_io.h"

namespace ricochet::study {

struct Curve {
  std::string title;
  std::vector<std::pair<double, double>> points;
  std::string style = "linespoints";  ///< gnuplot `with` clause
};

/// One PNG. The script lands in DIR/gnuplot/NAME.gp and draws DIR/NAME.png when gnuplot runs in
/// DIR. Points that a log axis cannot show (<= 0, not finite) are dropped and counted in the
/// report text.
struct Plot {
  std::string name;
  std::string title;
  std::string xlabel;
  std::string ylabel;
  bool logx = false;
  bool logy = false;
  std::vector<Curve> curves;
  std::vector<std::string> commands;  ///< extra gnuplot commands before `plot`
};

/// A cell of a table built from result rows: the metric whose row it reads, and how to print it.
struct Column {
  std::string title;
  std::string metric;
  std::function<std::string(const ResultRow&)> cell;
};

class Report {
 public:
  Report(std::string out_dir, const Results& results)
      : dir_(std::move(out_dir)), results_(results) {}

  const Results& results() const { return results_; }
  std::vector<std::string> precisions() const { return results_.precisions(); }

  /// One line for the summary at the top of the report, under the scene's name.
  void headline(const std::string& scene, const std::string& text);
  void heading(int level, const std::string& text);
  void text(const std::string& paragraph);
  void table(const std::vector<std::string>& header,
             const std::vector<std::vector<std::string>>& rows);
  /// Writes the gnuplot script and embeds the PNG; says so in the text when no point is left.
  void plot(const Plot& plot);
  /// For each knob, the settings that differ from base in that knob only, with every column once
  /// per precision. The base setting's rows are marked.
  void knob_table(const std::string& scene, const Setting& base, const std::vector<Knob>& knobs,
                  const std::vector<Column>& columns);
  /// Rows: values of knob `row`; columns: values of knob `column`; cell: one metric of one
  /// precision around base.
  void grid_table(const std::string& scene, const std::string& precision, const Setting& base,
                  Knob row, Knob column, const std::string& metric,
                  const std::function<std::string(const ResultRow&)>& cell);
  /// One curve per value of knob `curve` (and per precision when both are present) over the
  /// values of knob `along`; x and y from each row.
  std::vector<Curve> curves(const std::string& scene, const std::string& metric,
                            const Setting& base, Knob curve, Knob along,
                            const std::function<double(const ResultRow&)>& x,
                            const std::function<double(const ResultRow&)>& y) const;

  /// The points of one recorded series as a curve.
  Curve series_curve(const std::string& scene, const std::string& precision,
                     const std::string& series, const std::string& title,
                     const std::string& style) const;

  const std::string& markdown() const { return markdown_; }
  const std::vector<std::pair<std::string, std::string>>& headlines() const { return headlines_; }
  bool ok() const { return ok_; }

 private:
  std::string dir_;
  const Results& results_;
  std::string markdown_;
  std::vector<std::pair<std::string, std::string>> headlines_;
  bool ok_ = true;
};

// Cell formats.
std::string num(double value, int digits = 3);  ///< %.{digits}g, "—" when not finite
std::string percent(double fraction);           ///< 0.0123 → "1.23 %"
inline std::function<std::string(const ResultRow&)> error_cell(int digits = 3) {
  return [digits](const ResultRow& r) { return num(r.error, digits); };
}
inline std::string ms_cell(const ResultRow& r) {
  return num(r.ms_per_step, 3);
}

/// Writes report.md (and the gnuplot scripts) for merged results into out_dir.
bool write_report(const std::string& out_dir, const Results& results, const std::string& mode,
                  const std::string& revision);

}  // namespace ricochet::study
