#include "overview.h"

#include <fmt/format.h>

#include <stdexcept>

#include "ricochet/tools/json_text.h"

namespace ricochet::server {

namespace {

using tools::json_string;

std::string json_number(double value) {
  return fmt::format("{:.3f}", value);
}

std::string json_series(const std::deque<double>& values) {
  std::string out = "[";
  for (const double value : values) {
    if (out.size() > 1) out += ',';
    out += json_number(value);
  }
  return out + "]";
}

void keep_last(std::deque<double>& values, double value, std::size_t count) {
  values.push_back(value);
  while (values.size() > count) values.pop_front();
}

}  // namespace

Overview::Overview(std::size_t history) : history_(history) {
  if (history == 0) throw std::invalid_argument("Overview: history must be > 0 samples");
}

std::string Overview::update(proto::TimeUs now, const OverviewSample& sample) {
  if (!first_at_) {
    first_at_ = now;
    last_at_ = now;
    last_in_ = sample.bytes_in;
    last_out_ = sample.bytes_out;
  }
  const double elapsed_s = static_cast<double>(now - last_at_) / 1e6;
  const auto rate = [elapsed_s](std::uint64_t bytes, std::uint64_t before) {
    return elapsed_s > 0 && bytes >= before ? static_cast<double>(bytes - before) / elapsed_s : 0.0;
  };
  std::string json = fmt::format(
      R"({{"at_s":{},"server":{{"players":{},"matches":{},"bytes_in_per_s":{},)"
      R"("bytes_out_per_s":{},"db_queue_depth":{},"fleet":{}}},"matches":[)",
      json_number(static_cast<double>(now - *first_at_) / 1e6), sample.players,
      sample.matches.size(), json_number(rate(sample.bytes_in, last_in_)),
      json_number(rate(sample.bytes_out, last_out_)), sample.db_queue_depth, sample.fleet);
  last_at_ = now;
  last_in_ = sample.bytes_in;
  last_out_ = sample.bytes_out;

  std::map<std::uint32_t, TickHistory> kept;
  for (const OverviewMatch& match : sample.matches) {
    TickHistory& ticks = kept[match.id];
    if (const auto found = ticks_.find(match.id); found != ticks_.end()) {
      ticks = std::move(found->second);
    }
    keep_last(ticks.p50_ms, match.tick_p50_ms, history_);
    keep_last(ticks.p99_ms, match.tick_p99_ms, history_);
    if (json.back() != '[') json += ',';
    json += fmt::format(
        R"({{"id":{},"name":{},"map":{},"mode":{},"phase":{},"seated":{},"connected":{},)"
        R"("max_players":{},"leader":{},"leader_score":{},"time_left_s":{},"overruns":{},)"
        R"("tick_p50_ms":{},"tick_p99_ms":{}}})",
        match.id, json_string(match.name), json_string(match.map), json_string(match.mode),
        json_string(match.phase), match.seated, match.connected, match.max_players,
        match.leader.empty() ? "null" : json_string(match.leader), match.leader_score,
        match.time_left_s ? json_number(*match.time_left_s) : "null", match.overruns,
        json_series(ticks.p50_ms), json_series(ticks.p99_ms));
  }
  ticks_ = std::move(kept);

  json += R"(],"refusals":[)";
  bool first = true;
  for (const OverviewRefusal& refusal : sample.refusals) {
    if (refusal.count == 0) continue;
    if (!first) json += ',';
    first = false;
    json += fmt::format(R"({{"channel":{},"reason":{},"count":{}{}}})",
                        json_string(refusal.channel), json_string(refusal.reason), refusal.count,
                        refusal.expected ? R"(,"expected":true)" : "");
  }
  return json + "]}";
}

}  // namespace ricochet::server
