#include "ricochet/loadtest/server_figures.h"

#include <algorithm>
#include <charconv>
#include <cmath>
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

/// The field of TickQuantiles a ricochet_tick_seconds{quantile} sample fills; null for another.
double* quantile_field(TickQuantiles& tick, std::string_view quantile) {
  if (quantile == "0.5") return &tick.p50_ms;
  if (quantile == "0.95") return &tick.p95_ms;
  if (quantile == "0.99") return &tick.p99_ms;
  if (quantile == "1") return &tick.max_ms;
  return nullptr;
}

/// A process amount (seconds, bytes, descriptors) from untrusted text: a finite value >= 0, or
/// `field` left as it was and the bad value counted.
void set_amount(double& field, double value, int& bad_values) {
  if (std::isfinite(value) && value >= 0) {
    field = value;
  } else {
    ++bad_values;
  }
}

int as_int(double value) {
  return value >= 0 && value < 1e9 ? static_cast<int>(value) : 0;
}

}  // namespace

TickQuantiles TickQuantiles::worst_with(const TickQuantiles& other) const {
  return {std::max(p50_ms, other.p50_ms), std::max(p95_ms, other.p95_ms),
          std::max(p99_ms, other.p99_ms), std::max(max_ms, other.max_ms)};
}

TickQuantiles ServerFigures::worst_tick() const {
  TickQuantiles worst;
  for (const auto& [id, match] : by_match) {
    if (match.connected > 0) worst = worst.worst_with(match.tick);
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
    } else if (name == "process_open_fds") {
      set_amount(out.open_fds, sample.value, out.bad_values);
    } else if (name == "process_resident_memory_bytes") {
      set_amount(out.resident_bytes, sample.value, out.bad_values);
    } else if (name == "process_cpu_seconds_total") {
      set_amount(out.cpu_seconds, sample.value, out.bad_values);
    } else if (name == "ricochet_db_file_bytes") {
      out.db_bytes = sample.value;
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
    } else if (name == "ricochet_placement_tickets_total") {
      const std::string_view result = sample.label("result");
      double count = -1;
      set_amount(count, sample.value, out.bad_values);
      if (!result.empty() && count >= 0) out.placement_tickets[std::string(result)] = count;
    } else if (name == "ricochet_tick_phase_seconds_sum") {
      const std::string_view phase = sample.label("phase");
      if (!phase.empty()) out.phase_seconds[std::string(phase)] += sample.value;
    } else if (name == "ricochet_tick_seconds") {
      const auto id = match_id(sample);
      if (!id) continue;
      if (double* field = quantile_field(out.by_match[*id].tick, sample.label("quantile"))) {
        *field = sample.value * 1000.0;
      }
    }
  }
  return out;
}

}  // namespace ricochet::loadtest
