/// results.csv / series.csv writing, reading and sweep selection.

#include "results_io.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace ricochet::study {

const char* const kResultsHeader =
    "scene,precision,variant,integrator,dt,iterations,substeps,position_correction,ccd,sleep,"
    "metric,error,ms_per_step,steps_per_s,ms_per_sim_s,energy_drift,max_penetration,note";
const char* const kSeriesHeader = "scene,precision,series,x,y";

namespace {

constexpr std::size_t kResultsColumns = 18;
constexpr std::size_t kSeriesColumns = 5;

/// Commas become semicolons, line breaks and quotes spaces: one field, no quoting needed.
std::string sanitise(std::string text) {
  for (char& c : text) {
    if (c == ',') c = ';';
    if (c == '\n' || c == '\r' || c == '"') c = ' ';
  }
  return text;
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

bool parse_number(const std::string& text, double& out) {
  if (text.empty()) return false;
  char* end = nullptr;
  out = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size();
}

bool parse_int(const std::string& text, int& out) {
  double value = 0;
  if (!parse_number(text, value) || value != static_cast<int>(value)) return false;
  out = static_cast<int>(value);
  return true;
}

bool parse_switch(const std::string& text, bool& out) {
  if (text != "on" && text != "off") return false;
  out = text == "on";
  return true;
}

}  // namespace

bool write_results(const std::string& path, const std::vector<Row>& rows) {
  std::ofstream out(path);
  if (!out) {
    std::fprintf(stderr, "physics-study: cannot write %s\n", path.c_str());
    return false;
  }
  out << kResultsHeader << '\n';
  for (const Row& r : rows) {
    const Setting& s = r.setting;
    const double ms_per_sim_s = r.ms_per_step / s.step_s();
    out << format("%s,%s,%s,%s,%.9g,%d,%d,%s,%s,%s,%s,%.9g,%.6g,%.6g,%.6g,%.9g,%.9g,%s\n",
                  r.scene.c_str(), precision_name(), sanitise(s.variant).c_str(),
                  integrator_name(s.integrator), s.dt, s.iterations, s.substeps,
                  correction_name(s.correction), s.ccd ? "on" : "off", s.sleep ? "on" : "off",
                  r.metric.name.c_str(), r.metric.error, r.ms_per_step,
                  r.ms_per_step > 0 ? 1000 / r.ms_per_step : 0.0, ms_per_sim_s, r.energy_drift,
                  r.max_penetration, sanitise(r.metric.note).c_str());
  }
  return static_cast<bool>(out);
}

bool write_series(const std::string& path, const std::vector<SeriesRow>& series) {
  std::ofstream out(path);
  if (!out) {
    std::fprintf(stderr, "physics-study: cannot write %s\n", path.c_str());
    return false;
  }
  out << kSeriesHeader << '\n';
  for (const SeriesRow& s : series) {
    out << format("%s,%s,%s,%.9g,%.9g\n", s.scene.c_str(), precision_name(),
                  sanitise(s.point.series).c_str(), s.point.x, s.point.y);
  }
  return static_cast<bool>(out);
}

namespace {

/// Reads a CSV file that must start with `header`; calls `row(fields, where)` for every
/// non-empty line after it (`where` is "path:line: " for messages). `row` returns false, with
/// `problem` set, to stop.
template <class RowFn>
bool read_csv(const std::string& path, const char* header, std::string& problem, RowFn&& row) {
  std::ifstream in(path);
  if (!in) {
    problem = "cannot read " + path;
    return false;
  }
  std::string line;
  if (!std::getline(in, line) || line != header) {
    problem = path + ": first line must be the header '" + header + "'";
    return false;
  }
  for (int number = 2; std::getline(in, line); ++number) {
    if (!line.empty() && !row(split(line), path + ":" + std::to_string(number) + ": "))
      return false;
  }
  return true;
}

}  // namespace

bool Results::read_results(const std::string& path, std::string& problem) {
  return read_csv(path, kResultsHeader, problem,
                  [&](const std::vector<std::string>& f, const std::string& where) {
                    if (f.size() != kResultsColumns) {
                      problem = where + "expected " + std::to_string(kResultsColumns) +
                                " fields, got " + std::to_string(f.size());
                      return false;
                    }
                    ResultRow r;
                    r.scene = f[0];
                    r.precision = f[1];
                    r.setting.variant = f[2];
                    r.metric = f[10];
                    r.note = f[17];
                    const bool ok =
                        parse_integrator(f[3], r.setting.integrator) &&
                        parse_number(f[4], r.setting.dt) && parse_int(f[5], r.setting.iterations) &&
                        parse_int(f[6], r.setting.substeps) &&
                        parse_correction(f[7], r.setting.correction) &&
                        parse_switch(f[8], r.setting.ccd) && parse_switch(f[9], r.setting.sleep) &&
                        parse_number(f[11], r.error) && parse_number(f[12], r.ms_per_step) &&
                        parse_number(f[13], r.steps_per_s) && parse_number(f[14], r.ms_per_sim_s) &&
                        parse_number(f[15], r.energy_drift) &&
                        parse_number(f[16], r.max_penetration);
                    if (!ok) {
                      problem = where + "a field does not parse";
                      return false;
                    }
                    rows_.push_back(std::move(r));
                    return true;
                  });
}

bool Results::read_series(const std::string& path, std::string& problem) {
  return read_csv(path, kSeriesHeader, problem,
                  [&](const std::vector<std::string>& f, const std::string& where) {
                    SeriesResultRow r;
                    if (f.size() != kSeriesColumns || !parse_number(f[3], r.point.x) ||
                        !parse_number(f[4], r.point.y)) {
                      problem = where + "expected scene,precision,series,x,y";
                      return false;
                    }
                    r.scene = f[0];
                    r.precision = f[1];
                    r.point.series = f[2];
                    series_.push_back(std::move(r));
                    return true;
                  });
}

std::vector<std::string> Results::precisions() const {
  std::vector<std::string> out;
  for (const char* p : {"float", "double"}) {
    if (std::any_of(rows_.begin(), rows_.end(),
                    [&](const ResultRow& r) { return r.precision == p; }))
      out.emplace_back(p);
  }
  return out;
}

const char* knob_name(Knob knob) {
  switch (knob) {
    case kIntegrator:
      return "integrator";
    case kDt:
      return "dt";
    case kIterations:
      return "iterations";
    case kSubsteps:
      return "substeps";
    case kCorrection:
      return "position correction";
    case kCcd:
      return "continuous collision";
    case kSleep:
      return "sleep";
    case kVariant:
      return "variant";
  }
  return "?";
}

std::string knob_value(const Setting& s, Knob knob) {
  switch (knob) {
    case kIntegrator:
      return integrator_name(s.integrator);
    case kDt:
      return dt_label(s.dt);
    case kIterations:
      return std::to_string(s.iterations);
    case kSubsteps:
      return std::to_string(s.substeps);
    case kCorrection:
      return correction_name(s.correction);
    case kCcd:
      return s.ccd ? "on" : "off";
    case kSleep:
      return s.sleep ? "on" : "off";
    case kVariant:
      return s.variant;
  }
  return "?";
}

double knob_rank(const Setting& s, Knob knob) {
  switch (knob) {
    case kIntegrator:
      return static_cast<double>(s.integrator);
    case kDt:
      return 1 / s.dt;
    case kIterations:
      return s.iterations;
    case kSubsteps:
      return s.substeps;
    case kCorrection:
      return static_cast<double>(s.correction);
    case kCcd:
      return s.ccd;
    case kSleep:
      return s.sleep;
    case kVariant: {
      const auto equals = s.variant.find('=');
      return equals == std::string::npos ? 0 : std::strtod(s.variant.c_str() + equals + 1, nullptr);
    }
  }
  return 0;
}

namespace {
/// dt is written with 9 significant digits, so a value read back differs from the constant.
bool same_dt(double a, double b) {
  return std::abs(a - b) <= 1e-7 * std::max(std::abs(a), std::abs(b));
}
}  // namespace

bool same_except(const Setting& a, const Setting& b, unsigned free_knobs) {
  const auto fixed = [&](Knob k) { return (free_knobs & k) == 0; };
  return (!fixed(kIntegrator) || a.integrator == b.integrator) &&
         (!fixed(kDt) || same_dt(a.dt, b.dt)) &&
         (!fixed(kIterations) || a.iterations == b.iterations) &&
         (!fixed(kSubsteps) || a.substeps == b.substeps) &&
         (!fixed(kCorrection) || a.correction == b.correction) &&
         (!fixed(kCcd) || a.ccd == b.ccd) && (!fixed(kSleep) || a.sleep == b.sleep) &&
         (!fixed(kVariant) || a.variant == b.variant);
}

const ResultRow* Results::find(const std::string& scene, const std::string& precision,
                               const Setting& setting, const std::string& metric) const {
  for (const ResultRow& r : rows_) {
    if (r.scene == scene && r.precision == precision && r.metric == metric &&
        same_except(r.setting, setting, 0)) {
      return &r;
    }
  }
  return nullptr;
}

std::vector<const ResultRow*> Results::select(const std::string& scene,
                                              const std::string& precision,
                                              const std::string& metric, const Setting& base,
                                              unsigned free_knobs) const {
  std::vector<const ResultRow*> out;
  for (const ResultRow& r : rows_) {
    if (r.scene == scene && r.precision == precision && r.metric == metric &&
        same_except(r.setting, base, free_knobs)) {
      out.push_back(&r);
    }
  }
  return out;
}

std::vector<SeriesPoint> Results::points(const std::string& scene, const std::string& precision,
                                         const std::string& series) const {
  std::vector<SeriesPoint> out;
  for (const SeriesResultRow& r : series_) {
    if (r.scene == scene && r.precision == precision && r.point.series == series)
      out.push_back(r.point);
  }
  return out;
}

std::vector<std::string> Results::series_names(const std::string& scene) const {
  std::vector<std::string> out;
  for (const SeriesResultRow& r : series_) {
    if (r.scene == scene && std::find(out.begin(), out.end(), r.point.series) == out.end())
      out.push_back(r.point.series);
  }
  return out;
}

}  // namespace ricochet::study
