#include "ricochet/loadtest/fleet_plan.h"

namespace ricochet::loadtest {

std::vector<FleetPlan> plan_fleets(int first, int count, std::size_t servers) {
  std::vector<FleetPlan> by_server(servers);
  for (std::size_t s = 0; s < servers; ++s) by_server[s].server = s;
  for (int k = first; k < first + count; ++k) {
    by_server[static_cast<std::size_t>(k) % servers].bots.push_back(k);
  }
  std::vector<FleetPlan> out;
  for (FleetPlan& plan : by_server) {
    if (!plan.bots.empty()) out.push_back(std::move(plan));
  }
  return out;
}

}  // namespace ricochet::loadtest
