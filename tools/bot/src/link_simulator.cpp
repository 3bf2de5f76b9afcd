/// Latency, jitter, loss, duplication and reordering of one direction (link_simulator.h).

#include "ricochet/bot/link_simulator.h"

#include <algorithm>
#include <cmath>

namespace ricochet::bot {

namespace {

constexpr double kMinReorderHoldMs = 20;

bool within(double value, double low, double high) {
  return std::isfinite(value) && value >= low && value <= high;
}

std::string range_error(const char* field, const std::string& range, double value) {
  return std::string("sim ") + field + " must be " + range + ", got " + std::to_string(value);
}

}  // namespace

std::string LinkConfig::validate() const {
  if (!within(latency_ms, 0, 5000)) return range_error("latency_ms", "0..5000", latency_ms);
  if (!within(jitter_ms, 0, latency_ms)) {
    return range_error("jitter_ms", "0..latency_ms (" + std::to_string(latency_ms) + ")",
                       jitter_ms);
  }
  if (!within(loss, 0, 1)) return range_error("loss", "0..1", loss);
  if (!within(duplicate, 0, 1)) return range_error("duplicate", "0..1", duplicate);
  if (!within(reorder, 0, 1)) return range_error("reorder", "0..1", reorder);
  return {};
}

LinkSimulator::LinkSimulator(const LinkConfig& config, std::uint64_t seed)
    : config_(config), random_(seed) {}

proto::TimeUs LinkSimulator::delay_us() {
  std::uniform_real_distribution<double> jitter(-config_.jitter_ms, config_.jitter_ms);
  double delay_ms = config_.latency_ms + (config_.jitter_ms > 0 ? jitter(random_) : 0.0);
  if (config_.reorder > 0 && std::bernoulli_distribution(config_.reorder)(random_)) {
    delay_ms += std::max(kMinReorderHoldMs, 2 * config_.jitter_ms);
    ++counters_.reordered;
  }
  return static_cast<proto::TimeUs>(std::max(0.0, delay_ms) * 1000.0);
}

void LinkSimulator::send(std::vector<std::uint8_t> datagram, proto::TimeUs now) {
  ++counters_.sent;
  if (config_.loss > 0 && std::bernoulli_distribution(config_.loss)(random_)) {
    ++counters_.dropped;
    return;
  }
  if (config_.duplicate > 0 && std::bernoulli_distribution(config_.duplicate)(random_)) {
    ++counters_.duplicated;
    queue_.push({now + delay_us(), next_order_++, datagram});
  }
  queue_.push({now + delay_us(), next_order_++, std::move(datagram)});
}

bool LinkSimulator::poll(proto::TimeUs now, std::vector<std::uint8_t>& out) {
  if (queue_.empty() || queue_.top().due > now) return false;
  // top() is const; the element is moved out just before it is popped.
  out = std::move(const_cast<InFlight&>(queue_.top()).bytes);
  queue_.pop();
  ++counters_.delivered;
  return true;
}

std::optional<proto::TimeUs> LinkSimulator::next_due() const {
  if (queue_.empty()) return std::nullopt;
  return queue_.top().due;
}

}  // namespace ricochet::bot
