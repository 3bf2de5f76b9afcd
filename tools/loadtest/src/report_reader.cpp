// read_generator_report (merge.h): one generator's report.json, untrusted, into StepSummaries.
// Boost.JSON is compiled here, header-only (libboost1.81-dev ships it; nothing else links it).
#include <boost/json/src.hpp>
#include <cmath>

#include "ricochet/loadtest/merge.h"

namespace ricochet::loadtest {

namespace json = boost::json;

namespace {

/// The most numbers one sample array may hold (a run of 10000 bots scraped 4 times a second
/// for an hour pools about 1.4e8 RTTs; a merge of that is not what this is for).
constexpr std::size_t kMaxSamples = 20'000'000;
constexpr double kMaxAmount = 1e15;

/// Reads fields of one object at a path ("steps[1].servers[0]"), keeping the first error.
class Fields {
 public:
  Fields(const json::object& object, std::string path, std::string& error)
      : object_(object), path_(std::move(path)), error_(error) {}

  /// A finite number in [min, max]; `fallback` when absent and not `required`.
  double number(std::string_view key, double min = 0, double max = kMaxAmount, bool required = true,
                double fallback = 0) {
    const json::value* value = object_.if_contains(key);
    if (!value) {
      if (required) fail(key, "missing");
      return fallback;
    }
    boost::system::error_code ec;
    const double number = value->to_number<double>(ec);
    if (ec || !std::isfinite(number) || number < min || number > max) {
      fail(key, "expected a number " + text(min) + ".." + text(max) + ", got " +
                    json::serialize(*value).substr(0, 40));
      return fallback;
    }
    return number;
  }

  int count(std::string_view key) { return static_cast<int>(number(key, 0, 1e9)); }

  std::string string(std::string_view key, bool required = true) {
    const json::value* value = object_.if_contains(key);
    if (!value || !value->is_string()) {
      if (value || required) fail(key, "expected a string");
      return {};
    }
    const json::string& text = value->get_string();
    if (text.size() > 4096) fail(key, "longer than 4096 bytes");
    return std::string(text.data(), text.size());
  }

  bool boolean(std::string_view key) {
    const json::value* value = object_.if_contains(key);
    if (!value || !value->is_bool()) {
      fail(key, "expected true or false");
      return false;
    }
    return value->get_bool();
  }

  const json::object* object(std::string_view key) {
    const json::value* value = object_.if_contains(key);
    if (!value || !value->is_object()) {
      fail(key, "expected an object");
      return nullptr;
    }
    return &value->get_object();
  }

  const json::array* array(std::string_view key) {
    const json::value* value = object_.if_contains(key);
    if (!value || !value->is_array()) {
      fail(key, "expected an array");
      return nullptr;
    }
    return &value->get_array();
  }

  /// An array of finite numbers >= 0.
  std::vector<double> samples(std::string_view key) {
    std::vector<double> out;
    const json::array* values = array(key);
    if (!values) return out;
    if (values->size() > kMaxSamples) {
      fail(key, "more than " + std::to_string(kMaxSamples) + " samples");
      return out;
    }
    out.reserve(values->size());
    for (const json::value& value : *values) {
      boost::system::error_code ec;
      const double number = value.to_number<double>(ec);
      if (ec || !std::isfinite(number) || number < 0) {
        fail(key, "expected numbers >= 0, got " + json::serialize(value).substr(0, 40));
        return {};
      }
      out.push_back(number);
    }
    return out;
  }

  /// Every member a number in [0, kMaxAmount], into `out`.
  template <class Map>
  void numbers(std::string_view key, Map& out) {
    const json::object* members = object(key);
    if (!members) return;
    for (const auto& member : *members) {
      Fields each(*members, path_ + "." + std::string(key), error_);
      out[std::string(member.key())] =
          static_cast<typename Map::mapped_type>(each.number(member.key()));
    }
  }

  const std::string& path() const { return path_; }
  bool ok() const { return error_.empty(); }
  /// Whether `key` is present (a field a report from before it was added lacks).
  bool has(std::string_view key) const { return object_.if_contains(key) != nullptr; }

 private:
  static std::string text(double value) {
    char out[32];
    std::snprintf(out, sizeof out, "%g", value);
    return out;
  }
  void fail(std::string_view key, const std::string& what) {
    if (error_.empty())
      error_ = path_ + (path_.empty() ? "" : ".") + std::string(key) + ": " + what;
  }

  const json::object& object_;
  std::string path_;
  std::string& error_;
};

ServerWindow read_server(const json::object& object, const std::string& path, std::string& error) {
  Fields f(object, path, error);
  ServerWindow out;
  out.label = f.string("server");
  out.scraped = f.boolean("scraped");
  out.matches = f.count("matches");
  out.players = f.count("players");
  out.tick.p50_ms = f.number("tick_ms_p50");
  out.tick.p95_ms = f.number("tick_ms_p95");
  out.tick.p99_ms = f.number("tick_ms_p99");
  out.tick.max_ms = f.number("tick_ms_max");
  out.tick_p99_mean_ms = f.number("tick_ms_p99_mean_match");
  out.overruns = f.number("overruns");
  out.dropped_steps = f.number("dropped_steps");
  out.cpu_percent = f.number("cpu_percent", -1);
  out.rss_mb = f.number("rss_mb", -1);
  out.cpu_percent_proc = f.number("cpu_percent_proc", -1);
  out.rss_mb_proc = f.number("rss_mb_proc", -1);
  out.packets_in_per_s = f.number("packets_in_per_s");
  out.packets_out_per_s = f.number("packets_out_per_s");
  f.numbers("phase_percent", out.phase_percent);
  if (f.has("placement_tickets")) f.numbers("placement_tickets", out.placement_tickets);
  return out;
}

StepSummary read_step(const json::object& object, const std::string& path, std::string& error) {
  Fields f(object, path, error);
  StepSummary out;
  out.bots = f.count("bots");
  out.bots_connected = f.count("bots_connected");
  out.bots_gave_up = f.count("bots_gave_up");
  out.matches = f.count("matches");
  out.measured_s = f.number("measured_s");
  out.ramp_s = f.number("ramp_s");
  out.server_tick.p50_ms = f.number("server_tick_ms_p50");
  out.server_tick.p95_ms = f.number("server_tick_ms_p95");
  out.server_tick.p99_ms = f.number("server_tick_ms_p99");
  out.server_tick.max_ms = f.number("server_tick_ms_max");
  out.server_tick_ms_p99_mean = f.number("server_tick_ms_p99_mean_match");
  out.snapshot_loss = f.number("snapshot_loss", 0, 1);
  out.snapshots_per_s_per_bot = f.number("snapshots_per_s_per_bot");
  out.kbps_in_per_client = f.number("kbps_in_per_client");
  out.kbps_out_per_client = f.number("kbps_out_per_client");
  out.kbps_in_total = f.number("kbps_in_total");
  out.kbps_out_total = f.number("kbps_out_total");
  out.generator_cpu_percent = f.number("generator_cpu_percent");
  out.generator_rss_mb = f.number("generator_rss_mb");
  out.snapshots_received = f.number("snapshots_received");
  out.snapshots_lost = f.number("snapshots_lost");
  out.rtt_ms_samples = f.samples("rtt_ms_samples");
  out.connect_ms_samples = f.samples("connect_ms_samples");
  // Placement (--find-match): absent from reports of before it.
  if (f.has("placement_ms_samples")) out.placement_ms_samples = f.samples("placement_ms_samples");
  if (f.has("bots_placed")) f.numbers("bots_placed", out.bots_placed);
  f.numbers("errors", out.errors);
  if (const json::array* servers = f.array("servers")) {
    for (std::size_t i = 0; i < servers->size() && f.ok(); ++i) {
      const std::string at = path + ".servers[" + std::to_string(i) + "]";
      if (!(*servers)[i].is_object()) {
        error = at + ": expected an object";
        break;
      }
      out.servers.push_back(read_server((*servers)[i].get_object(), at, error));
    }
  }
  if (f.ok() && out.bots_connected > out.bots) {
    error = path + ": bots_connected " + std::to_string(out.bots_connected) + " > bots " +
            std::to_string(out.bots);
  }
  out.total_servers();
  return out;
}

}  // namespace

std::variant<GeneratorReport, std::string> read_generator_report(std::string_view text,
                                                                 const std::string& source) {
  if (text.size() > kMaxReportBytes) {
    return source + ": " + std::to_string(text.size()) + " bytes, at most " +
           std::to_string(kMaxReportBytes) + " read";
  }
  json::parse_options options;
  options.max_depth = 16;
  boost::system::error_code ec;
  const json::value root = json::parse(text, ec, {}, options);
  if (ec) return source + ": not JSON (" + ec.message() + "; truncated?)";
  if (!root.is_object()) return source + ": expected a JSON object";
  const json::object& object = root.get_object();
  std::string error;
  Fields f(object, "", error);
  GeneratorReport out;
  out.source = source;
  if (f.string("tool") != "ricochet-loadtest" && f.ok()) {
    return source + ": not a ricochet-loadtest report (\"tool\")";
  }
  if (object.if_contains("mode")) return source + ": a soak's report, not a load test's";
  out.measured_at_utc = f.string("measured_at_utc");
  out.command = f.string("command");
  if (const json::array* steps = f.array("steps")) {
    if (steps->empty() && f.ok()) return source + ": no step was measured";
    for (std::size_t i = 0; i < steps->size() && error.empty(); ++i) {
      const std::string at = "steps[" + std::to_string(i) + "]";
      if (!(*steps)[i].is_object()) {
        error = at + ": expected an object";
        break;
      }
      out.steps.push_back(read_step((*steps)[i].get_object(), at, error));
    }
  }
  if (!error.empty()) return source + ": " + error;
  return out;
}

}  // namespace ricochet::loadtest
