#pragma once
/// results.csv and series.csv: writing a run's rows, reading merged files back, and selecting
/// the rows of a sweep (everything equal to a scene's base setting except some knobs).
///
/// Fields never contain commas or quotes (notes are sanitised on writing), so a line splits on
/// ',' and the files read with awk -F, too.

#include <string>
#include <vector>

#include "study.h"

namespace ricochet::study {

/// The column names of results.csv, in order.
extern const char* const kResultsHeader;
/// The column names of series.csv, in order.
extern const char* const kSeriesHeader;

/// Writes rows (precision from this binary) to path; false with a message on stderr on failure.
bool write_results(const std::string& path, const std::vector<Row>& rows);
bool write_series(const std::string& path, const std::vector<SeriesRow>& series);

/// One row of results.csv as read back.
struct ResultRow {
  std::string scene;
  std::string precision;
  Setting setting;
  std::string metric;
  double error = 0;
  double ms_per_step = 0;
  double steps_per_s = 0;
  double ms_per_sim_s = 0;
  double energy_drift = 0;
  double max_penetration = 0;
  std::string note;
};

struct SeriesResultRow {
  std::string scene;
  std::string precision;
  SeriesPoint point;
};

/// The knobs of a Setting, as bits: which ones a selection lets vary.
enum Knob : unsigned {
  kIntegrator = 1u << 0,
  kDt = 1u << 1,
  kIterations = 1u << 2,
  kSubsteps = 1u << 3,
  kCorrection = 1u << 4,
  kCcd = 1u << 5,
  kSleep = 1u << 6,
  kVariant = 1u << 7,
};
const char* knob_name(Knob knob);
/// The knob's value in a setting, as the report prints it ("1/60", "SoftStep", "on").
std::string knob_value(const Setting& s, Knob knob);
/// Sort key of the knob's value: dt coarse to fine, counts ascending, enums in declaration order,
/// variants by the number after '='.
double knob_rank(const Setting& s, Knob knob);
/// True when a and b agree on every knob not in `free_knobs`.
bool same_except(const Setting& a, const Setting& b, unsigned free_knobs);

class Results {
 public:
  /// Appends the rows of a results.csv (any precision); false with `problem` set on a bad file.
  bool read_results(const std::string& path, std::string& problem);
  bool read_series(const std::string& path, std::string& problem);

  const std::vector<ResultRow>& rows() const { return rows_; }
  const std::vector<SeriesResultRow>& series() const { return series_; }
  /// Precisions present, float first.
  std::vector<std::string> precisions() const;

  /// The row of exactly this setting and metric, or null.
  const ResultRow* find(const std::string& scene, const std::string& precision,
                        const Setting& setting, const std::string& metric) const;
  /// Rows of a metric whose setting equals base except in free_knobs, in file (run) order.
  std::vector<const ResultRow*> select(const std::string& scene, const std::string& precision,
                                       const std::string& metric, const Setting& base,
                                       unsigned free_knobs) const;
  /// Points of one series, in file order.
  std::vector<SeriesPoint> points(const std::string& scene, const std::string& precision,
                                  const std::string& series) const;
  /// Distinct series names of a scene, in file order.
  std::vector<std::string> series_names(const std::string& scene) const;

 private:
  std::vector<ResultRow> rows_;
  std::vector<SeriesResultRow> series_;
};

}  // namespace ricochet::study
