#include "ricochet/loadtest/capacity.h"

#include <algorithm>

namespace ricochet::loadtest {

const char* name(CapacityShortfall shortfall) {
  switch (shortfall) {
    case CapacityShortfall::NotMeasured:
      return "not_measured";
    case CapacityShortfall::BotsMissing:
      return "bots_missing";
    case CapacityShortfall::TickP99:
      return "tick_p99";
    case CapacityShortfall::Overruns:
      return "overruns";
    case CapacityShortfall::SnapshotLoss:
      return "snapshot_loss";
    case CapacityShortfall::ServerCpu:
      return "server_cpu";
  }
  return "unknown";
}

std::vector<CapacityShortfall> capacity_shortfalls(const StepSummary& step,
                                                   const CapacityCriteria& criteria) {
  std::vector<CapacityShortfall> missed;
  if (!(step.measured_s > 0)) missed.push_back(CapacityShortfall::NotMeasured);
  if (step.bots_connected != step.bots) missed.push_back(CapacityShortfall::BotsMissing);
  if (!(step.server_tick.p99_ms <= criteria.max_tick_p99_ms)) {
    missed.push_back(CapacityShortfall::TickP99);
  }
  if (!(step.overruns <= criteria.max_overruns)) missed.push_back(CapacityShortfall::Overruns);
  if (!(step.snapshot_loss <= criteria.max_snapshot_loss)) {
    missed.push_back(CapacityShortfall::SnapshotLoss);
  }
  if (!(step.server_cpu_percent < criteria.server_cpu_percent_below)) {
    missed.push_back(CapacityShortfall::ServerCpu);
  }
  return missed;
}

int capacity_bots(const std::vector<StepSummary>& steps) {
  int best = 0;
  for (const StepSummary& step : steps) {
    if (step.meets_capacity()) best = std::max(best, step.bots);
  }
  return best;
}

}  // namespace ricochet::loadtest
