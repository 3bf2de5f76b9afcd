#include "ricochet/server/metrics.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <set>
#include <stdexcept>

namespace ricochet::server {
namespace {

enum class MetricType { Counter, Gauge, Histogram, Summary };

const char* type_name(MetricType type) {
  switch (type) {
    case MetricType::Counter:
      return "counter";
    case MetricType::Gauge:
      return "gauge";
    case MetricType::Histogram:
      return "histogram";
    case MetricType::Summary:
      return "summary";
  }
  return "untyped";
}

bool is_metric_name(std::string_view name) {
  if (name.empty()) return false;
  for (std::size_t i = 0; i < name.size(); ++i) {
    const char c = name[i];
    const bool letter = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_' || c == ':';
    const bool digit = c >= '0' && c <= '9';
    if (!letter && !(digit && i > 0)) return false;
  }
  return true;
}

bool is_label_name(std::string_view name) {
  if (name.empty() || name.starts_with("__")) return false;
  for (std::size_t i = 0; i < name.size(); ++i) {
    const char c = name[i];
    const bool letter = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
    const bool digit = c >= '0' && c <= '9';
    if (!letter && !(digit && i > 0)) return false;
  }
  return true;
}

void check_names(std::string_view name, const MetricLabels& labels, MetricType type) {
  if (!is_metric_name(name)) {
    throw std::invalid_argument("metric name must match [a-zA-Z_:][a-zA-Z0-9_:]*, got \"" +
                                std::string{name} + "\"");
  }
  std::set<std::string_view> seen;
  for (const auto& [label, value] : labels) {
    if (!is_label_name(label)) {
      throw std::invalid_argument(
          "label name of " + std::string{name} +
          " must match [a-zA-Z_][a-zA-Z0-9_]* without a leading __, got \"" + label + "\"");
    }
    if (type == MetricType::Histogram && label == "le") {
      throw std::invalid_argument("histogram " + std::string{name} +
                                  " cannot have a label \"le\" (it names the buckets)");
    }
    if (type == MetricType::Summary && label == "quantile") {
      throw std::invalid_argument("summary " + std::string{name} +
                                  " cannot have a label \"quantile\" (it names the quantiles)");
    }
    if (!seen.insert(label).second) {
      throw std::invalid_argument("label \"" + label + "\" given twice for " + std::string{name});
    }
  }
}

/// Go's strconv.ParseFloat reads all of these: "NaN", "+Inf", "-Inf", shortest round trip.
std::string format_value(double value) {
  if (std::isnan(value)) return "NaN";
  if (std::isinf(value)) return value > 0 ? "+Inf" : "-Inf";
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string{buffer, result.ptr};
}

void append_escaped_label_value(std::string& out, std::string_view value) {
  for (const char c : value) {
    if (c == '\\') {
      out += "\\\\";
    } else if (c == '"') {
      out += "\\\"";
    } else if (c == '\n') {
      out += "\\n";
    } else {
      out += c;
    }
  }
}

std::string escape_help(std::string_view help) {
  std::string out;
  for (const char c : help) {
    if (c == '\\') {
      out += "\\\\";
    } else if (c == '\n') {
      out += "\\n";
    } else {
      out += c;
    }
  }
  return out;
}

/// `{a="x",b="y"}` (plus `extra` last when given), or nothing without labels.
std::string format_labels(const MetricLabels& labels, std::string_view extra_name = {},
                          std::string_view extra_value = {}) {
  if (labels.empty() && extra_name.empty()) return {};
  std::string out = "{";
  bool first = true;
  auto add = [&](std::string_view name, std::string_view value) {
    if (!first) out += ',';
    first = false;
    out += name;
    out += "=\"";
    append_escaped_label_value(out, value);
    out += '"';
  };
  for (const auto& [name, value] : labels) add(name, value);
  if (!extra_name.empty()) add(extra_name, extra_value);
  out += '}';
  return out;
}

/// One series as a scrape renders it.
struct SeriesValue {
  MetricLabels labels;
  double value = 0.0;
  HistogramSnapshot histogram;
  SummarySnapshot summary;
};

/// One family as a scrape renders it.
struct FamilyValue {
  MetricType type = MetricType::Counter;
  std::string help;
  std::vector<SeriesValue> series;
  std::set<std::string> label_keys;  ///< format_labels of each series: duplicates are refused
};

using Scrape = std::map<std::string, FamilyValue, std::less<>>;

FamilyValue& family_of(Scrape& scrape, std::string_view name, std::string_view help,
                       MetricType type) {
  auto it = scrape.find(name);
  if (it == scrape.end()) {
    it = scrape.emplace(std::string{name}, FamilyValue{type, std::string{help}, {}, {}}).first;
  } else if (it->second.type != type || it->second.help != help) {
    throw std::invalid_argument("metric " + std::string{name} + " reported as " + type_name(type) +
                                " \"" + std::string{help} + "\" but registered as " +
                                type_name(it->second.type) + " \"" + it->second.help + "\"");
  }
  return it->second;
}

void add_series(FamilyValue& family, std::string_view name, SeriesValue series) {
  if (!family.label_keys.insert(format_labels(series.labels)).second) {
    throw std::invalid_argument("series " + std::string{name} + format_labels(series.labels) +
                                " reported twice");
  }
  family.series.push_back(std::move(series));
}

/// The sink given to collect callbacks: adds to the scrape.
class ScrapeSink final : public MetricsSink {
 public:
  explicit ScrapeSink(Scrape& scrape) : scrape_(scrape) {}

  void counter(std::string_view name, std::string_view help, const MetricLabels& labels,
               double value) override {
    add(name, help, MetricType::Counter, SeriesValue{labels, value, {}, {}});
  }
  void gauge(std::string_view name, std::string_view help, const MetricLabels& labels,
             double value) override {
    add(name, help, MetricType::Gauge, SeriesValue{labels, value, {}, {}});
  }
  void histogram(std::string_view name, std::string_view help, const MetricLabels& labels,
                 const HistogramSnapshot& histogram) override {
    if (histogram.bucket_counts.size() != histogram.upper_bounds.size() + 1) {
      throw std::invalid_argument("histogram " + std::string{name} + " has " +
                                  std::to_string(histogram.upper_bounds.size()) +
                                  " bounds, so needs that many + 1 bucket counts, got " +
                                  std::to_string(histogram.bucket_counts.size()));
    }
    add(name, help, MetricType::Histogram, SeriesValue{labels, 0.0, histogram, {}});
  }
  void summary(std::string_view name, std::string_view help, const MetricLabels& labels,
               const SummarySnapshot& summary) override {
    for (const auto& [quantile, value] : summary.quantiles) {
      if (!(quantile >= 0.0 && quantile <= 1.0)) {
        throw std::invalid_argument("summary " + std::string{name} + ": quantile " +
                                    format_value(quantile) + " is not in 0..1");
      }
    }
    add(name, help, MetricType::Summary, SeriesValue{labels, 0.0, {}, summary});
  }

 private:
  void add(std::string_view name, std::string_view help, MetricType type, SeriesValue series) {
    check_names(name, series.labels, type);
    add_series(family_of(scrape_, name, help, type), name, std::move(series));
  }

  Scrape& scrape_;
};

void render_family(std::string& out, const std::string& name, const FamilyValue& family) {
  out += "# HELP " + name + ' ' + escape_help(family.help) + '\n';
  out += "# TYPE " + name + ' ' + type_name(family.type) + '\n';
  for (const SeriesValue& series : family.series) {
    if (family.type == MetricType::Summary) {
      const SummarySnapshot& summary = series.summary;
      for (const auto& [quantile, value] : summary.quantiles) {
        out += name + format_labels(series.labels, "quantile", format_value(quantile)) + ' ' +
               format_value(value) + '\n';
      }
      out += name + "_sum" + format_labels(series.labels) + ' ' + format_value(summary.sum) + '\n';
      out += name + "_count" + format_labels(series.labels) + ' ' + std::to_string(summary.count) +
             '\n';
      continue;
    }
    if (family.type != MetricType::Histogram) {
      out += name + format_labels(series.labels) + ' ' + format_value(series.value) + '\n';
      continue;
    }
    const HistogramSnapshot& histogram = series.histogram;
    std::uint64_t cumulative = 0;
    for (std::size_t i = 0; i < histogram.upper_bounds.size(); ++i) {
      cumulative += histogram.bucket_counts[i];
      out += name + "_bucket" +
             format_labels(series.labels, "le", format_value(histogram.upper_bounds[i])) + ' ' +
             std::to_string(cumulative) + '\n';
    }
    cumulative += histogram.bucket_counts.back();
    out += name + "_bucket" + format_labels(series.labels, "le", "+Inf") + ' ' +
           std::to_string(cumulative) + '\n';
    out += name + "_sum" + format_labels(series.labels) + ' ' + format_value(histogram.sum) + '\n';
    out += name + "_count" + format_labels(series.labels) + ' ' + std::to_string(cumulative) + '\n';
  }
}

}  // namespace

Histogram::Histogram(std::vector<double> upper_bounds) : upper_bounds_(std::move(upper_bounds)) {
  if (upper_bounds_.empty()) throw std::invalid_argument("a histogram needs at least one bound");
  for (std::size_t i = 0; i < upper_bounds_.size(); ++i) {
    if (!std::isfinite(upper_bounds_[i]) || (i > 0 && upper_bounds_[i] <= upper_bounds_[i - 1])) {
      throw std::invalid_argument("histogram bounds must be finite and strictly increasing, got " +
                                  format_value(upper_bounds_[i]) + " at index " +
                                  std::to_string(i));
    }
  }
  bucket_counts_ = std::make_unique<std::atomic<std::uint64_t>[]>(upper_bounds_.size() + 1);
}

void Histogram::observe(double value) {
  const std::size_t bucket =
      std::isnan(value) ? upper_bounds_.size()
                        : static_cast<std::size_t>(
                              std::lower_bound(upper_bounds_.begin(), upper_bounds_.end(), value) -
                              upper_bounds_.begin());
  bucket_counts_[bucket].fetch_add(1, std::memory_order_relaxed);
  sum_.fetch_add(value, std::memory_order_relaxed);
}

HistogramSnapshot Histogram::snapshot() const {
  HistogramSnapshot snapshot{upper_bounds_, {}, sum_.load(std::memory_order_relaxed)};
  snapshot.bucket_counts.reserve(upper_bounds_.size() + 1);
  for (std::size_t i = 0; i <= upper_bounds_.size(); ++i) {
    snapshot.bucket_counts.push_back(bucket_counts_[i].load(std::memory_order_relaxed));
  }
  return snapshot;
}

std::vector<double> exponential_buckets(double start, double factor, int count) {
  if (!(start > 0) || !(factor > 1) || count < 1) {
    throw std::invalid_argument(
        "exponential_buckets needs start > 0, factor > 1, count >= 1, got " + format_value(start) +
        ", " + format_value(factor) + ", " + std::to_string(count));
  }
  std::vector<double> bounds;
  double bound = start;
  for (int i = 0; i < count; ++i, bound *= factor) bounds.push_back(bound);
  return bounds;
}

struct MetricsRegistry::Family {
  MetricType type;
  std::string help;
  std::vector<double> upper_bounds;  ///< histograms: the family's bounds
  struct Series {
    MetricLabels labels;
    std::unique_ptr<Counter> counter;
    std::unique_ptr<Gauge> gauge;
    std::unique_ptr<Histogram> histogram;
  };
  std::vector<Series> series;

  Series* find(const MetricLabels& labels) {
    for (Series& s : series) {
      if (s.labels == labels) return &s;
    }
    return nullptr;
  }
};

MetricsRegistry::MetricsRegistry() = default;
MetricsRegistry::~MetricsRegistry() = default;

MetricsRegistry::Family& MetricsRegistry::family(const std::string& name, const std::string& help,
                                                 int type) {
  const auto metric_type = static_cast<MetricType>(type);
  auto it = families_.find(name);
  if (it == families_.end()) {
    it = families_.emplace(name, std::make_unique<Family>(Family{metric_type, help, {}, {}})).first;
  } else if (it->second->type != metric_type || it->second->help != help) {
    throw std::invalid_argument("metric " + name + " registered as " + type_name(metric_type) +
                                " \"" + help + "\" but already exists as " +
                                type_name(it->second->type) + " \"" + it->second->help + "\"");
  }
  return *it->second;
}

Counter& MetricsRegistry::counter(const std::string& name, const std::string& help,
                                  const MetricLabels& labels) {
  check_names(name, labels, MetricType::Counter);
  const std::lock_guard lock{mutex_};
  Family& f = family(name, help, static_cast<int>(MetricType::Counter));
  if (Family::Series* series = f.find(labels)) return *series->counter;
  f.series.push_back({labels, std::make_unique<Counter>(), nullptr, nullptr});
  return *f.series.back().counter;
}

Gauge& MetricsRegistry::gauge(const std::string& name, const std::string& help,
                              const MetricLabels& labels) {
  check_names(name, labels, MetricType::Gauge);
  const std::lock_guard lock{mutex_};
  Family& f = family(name, help, static_cast<int>(MetricType::Gauge));
  if (Family::Series* series = f.find(labels)) return *series->gauge;
  f.series.push_back({labels, nullptr, std::make_unique<Gauge>(), nullptr});
  return *f.series.back().gauge;
}

Histogram& MetricsRegistry::histogram(const std::string& name, const std::string& help,
                                      const std::vector<double>& upper_bounds,
                                      const MetricLabels& labels) {
  check_names(name, labels, MetricType::Histogram);
  auto made = std::make_unique<Histogram>(upper_bounds);  // checks the bounds
  const std::lock_guard lock{mutex_};
  Family& f = family(name, help, static_cast<int>(MetricType::Histogram));
  if (f.series.empty()) {
    f.upper_bounds = upper_bounds;
  } else if (f.upper_bounds != upper_bounds) {
    throw std::invalid_argument("histogram " + name + " registered again with other bucket bounds");
  }
  if (Family::Series* series = f.find(labels)) return *series->histogram;
  f.series.push_back({labels, nullptr, nullptr, std::move(made)});
  return *f.series.back().histogram;
}

void MetricsRegistry::add_collect_callback(CollectCallback callback) {
  const std::lock_guard lock{mutex_};
  collect_callbacks_.push_back(std::move(callback));
}

std::string MetricsRegistry::render() const {
  Scrape scrape;
  std::vector<CollectCallback> callbacks;
  {
    const std::lock_guard lock{mutex_};
    for (const auto& [name, family] : families_) {
      FamilyValue& value = family_of(scrape, name, family->help, family->type);
      for (const Family::Series& series : family->series) {
        SeriesValue series_value{series.labels, 0.0, {}, {}};
        if (series.counter) series_value.value = series.counter->value();
        if (series.gauge) series_value.value = series.gauge->value();
        if (series.histogram) series_value.histogram = series.histogram->snapshot();
        add_series(value, name, std::move(series_value));
      }
    }
    callbacks = collect_callbacks_;
  }
  ScrapeSink sink{scrape};
  for (const CollectCallback& callback : callbacks) callback(sink);

  std::string out;
  for (const auto& [name, family] : scrape) render_family(out, name, family);
  return out;
}

}  // namespace ricochet::server
