#include "ricochet/loadtest/server_figures.h"

#include <algorithm>
#include <charconv>
#include <optional>
#include <string_view>

namespace ricochet::loadtest {

namespace {

std::optional<std::uint32_t> match_id(const MetricSample& sample) {
  const std::string_view text = sample.label("match");
  std::uint32_t id = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), id);
  if (error != std::errc{} || end != text.data() + text.size() || text.empty()) {
    return std::nullopt;
  }
  return id;
}

int quantile_index(std::string_view quantile) {
  if (quantile == "0.5") return 0;
  if (quantile == "0.95") return 1;
  if (quantile == "0.99") return 2;
  if (quantile == "1") return 3;
  return -1;
}

int as_int(double value) {
  return value >= 0 && value < 1e9 ? static_cast<int>(value) : 0;
}

}  // namespace

std::array<double, 4> ServerFigures::worst_tick_ms() const {
  std::array<double, 4> worst{};
  for (const auto& [id, match] : by_match) {
    if (match.connected == 0) continue;
    for (std::size_t i = 0; i < worst.size(); ++i) worst[i] = std::max(worst[i], match.tick_ms[i]);
  }
  return worst;
}

ServerFigures read_server_figures(const std::vector<MetricSample>& samples) {
  ServerFigures out;
  for (const MetricSample& sample : samples) {
    const std::string& name = sample.name;
    const bool in = sample.label("direction") == "in";
    if (name == "ricochet_process_id") {
      out.pid = as_int(sample.value);
    } else if (name == "ricochet_matches") {
      out.matches = as_int(sample.value);
    } else if (name == "ricochet_players") {
      out.players = as_int(sample.value);
    } else if (name == "ricochet_game_connections" && sample.label("state") == "connected") {
      out.game_connected = as_int(sample.value);
    } else if (name == "ricochet_game_packets_total") {
      (in ? out.packets_in : out.packets_out) = sample.value;
    } else if (name == "ricochet_game_bytes_total") {
      (in ? out.bytes_in : out.bytes_out) = sample.value;
    } else if (name == "ricochet_game_dropped_total") {
      out.game_dropped += sample.value;
    } else if (name == "ricochet_control_refused_total") {
      out.control_refused += sample.value;
    } else if (name == "ricochet_match_dropped_steps_total") {
      out.dropped_steps += sample.value;
    } else if (name == "ricochet_match_overruns_total") {
      out.overruns += sample.value;
      if (const auto id = match_id(sample)) out.by_match[*id].overruns = sample.value;
    } else if (name == "ricochet_match_players" && sample.label("state") == "connected") {
      if (const auto id = match_id(sample)) out.by_match[*id].connected = as_int(sample.value);
    } else if (name == "ricochet_tick_phase_seconds_sum") {
      const std::string_view phase = sample.label("phase");
      if (!phase.empty()) out.phase_seconds[std::string(phase)] += sample.value;
    } else if (name == "ricochet_tick_seconds") {
      const int index = quantile_index(sample.label("quantile"));
      const auto id = match_id(sample);
      if (index >= 0 && id) {
        out.by_match[*id].tick_ms[static_cast<std::size_t>(index)] = sample.value * 1000.0;
      }
    }
  }
  return out;
}

}  // namespace ricochet::loadtest
