#pragma once
/// A small thread-safe metrics registry rendered in the Prometheus text exposition format 0.0.4.
///
/// Two sources of values:
///  - metrics the registry owns (Counter, Gauge, Histogram): hot code keeps a reference and
///    updates it with a relaxed atomic operation from any thread;
///  - collect callbacks, run at every scrape, that report values owned elsewhere (transport
///    counters, queue depths, per-match gauges) into a MetricsSink; what they stop reporting
///    disappears from the next scrape.
/// Families are rendered sorted by name, each with one HELP and one TYPE line; series in the order
/// they were registered, then reported. Names follow Prometheus rules: metric
/// [a-zA-Z_:][a-zA-Z0-9_:]*, label [a-zA-Z_][a-zA-Z0-9_]* not starting with "__"; a histogram
/// has no label "le", a summary none "quantile". Breaking a rule is a programming error:
/// std::invalid_argument.

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace ricochet::server {

/// Label name and value pairs, rendered in this order. Values may hold any bytes; they are
/// escaped (backslash, double quote, line feed).
using MetricLabels = std::vector<std::pair<std::string, std::string>>;

/// The Content-Type of MetricsRegistry::render()'s text.
inline constexpr std::string_view kPrometheusContentType =
    "text/plain; version=0.0.4; charset=utf-8";

/// A value that only goes up (restarts at 0 with the process).
class Counter {
 public:
  /// amount >= 0.
  void inc(double amount = 1.0) { value_.fetch_add(amount, std::memory_order_relaxed); }
  double value() const { return value_.load(std::memory_order_relaxed); }

 private:
  std::atomic<double> value_{0.0};
};

/// A value that goes up and down.
class Gauge {
 public:
  void set(double value) { value_.store(value, std::memory_order_relaxed); }
  void add(double amount) { value_.fetch_add(amount, std::memory_order_relaxed); }
  double value() const { return value_.load(std::memory_order_relaxed); }

 private:
  std::atomic<double> value_{0.0};
};

/// Counts per bucket, as a scrape sees them.
struct HistogramSnapshot {
  std::vector<double> upper_bounds;          ///< strictly increasing, finite; +Inf is implied
  std::vector<std::uint64_t> bucket_counts;  ///< upper_bounds.size() + 1, not cumulative
                                             ///< (the last is above every bound, NaN included)
  double sum = 0.0;
};

/// Quantiles of the observations in a window, and the sum and count of every observation, as a
/// scrape sees them (a Prometheus summary).
struct SummarySnapshot {
  std::vector<std::pair<double, double>> quantiles;  ///< (quantile 0..1, value), rendered in order
  double sum = 0.0;                                  ///< of every observation since the start
  std::uint64_t count = 0;                           ///< observations since the start
};

/// Observations counted into fixed buckets (value <= bound); also their sum.
class Histogram {
 public:
  /// Bounds strictly increasing and finite, at least one; else std::invalid_argument.
  explicit Histogram(std::vector<double> upper_bounds);
  void observe(double value);
  HistogramSnapshot snapshot() const;
  const std::vector<double>& upper_bounds() const { return upper_bounds_; }

 private:
  std::vector<double> upper_bounds_;
  std::unique_ptr<std::atomic<std::uint64_t>[]> bucket_counts_;
  std::atomic<double> sum_{0.0};
};

/// `count` bounds start, start*factor, start*factor^2, ... (start > 0, factor > 1, count >= 1).
std::vector<double> exponential_buckets(double start, double factor, int count);

/// What a collect callback reports into at scrape time. Reporting a name registered with another
/// type or help text, or the same series twice, is std::invalid_argument.
class MetricsSink {
 public:
  virtual ~MetricsSink() = default;
  virtual void counter(std::string_view name, std::string_view help, const MetricLabels& labels,
                       double value) = 0;
  virtual void gauge(std::string_view name, std::string_view help, const MetricLabels& labels,
                     double value) = 0;
  virtual void histogram(std::string_view name, std::string_view help, const MetricLabels& labels,
                         const HistogramSnapshot& histogram) = 0;
  virtual void summary(std::string_view name, std::string_view help, const MetricLabels& labels,
                       const SummarySnapshot& summary) = 0;
};

class MetricsRegistry {
 public:
  using CollectCallback = std::function<void(MetricsSink&)>;

  MetricsRegistry();
  ~MetricsRegistry();
  MetricsRegistry(const MetricsRegistry&) = delete;
  MetricsRegistry& operator=(const MetricsRegistry&) = delete;

  /// The series `name{labels}`, made on first call; the reference stays valid as long as the
  /// registry. The same name again must come with the same help text (and, for histograms, the
  /// same bounds).
  Counter& counter(const std::string& name, const std::string& help,
                   const MetricLabels& labels = {});
  Gauge& gauge(const std::string& name, const std::string& help, const MetricLabels& labels = {});
  Histogram& histogram(const std::string& name, const std::string& help,
                       const std::vector<double>& upper_bounds, const MetricLabels& labels = {});

  /// Runs at every render(), on the rendering thread, without the registry's lock held (it may
  /// register metrics). It must be thread-safe towards the code that owns the values it reads.
  void add_collect_callback(CollectCallback callback);

  /// Everything in the text exposition format 0.0.4 (kPrometheusContentType).
  std::string render() const;

 private:
  struct Family;
  Family& family(const std::string& name, const std::string& help, int type);

  mutable std::mutex mutex_;
  std::map<std::string, std::unique_ptr<Family>, std::less<>> families_;
  std::vector<CollectCallback> collect_callbacks_;
};

}  // namespace ricochet::server
