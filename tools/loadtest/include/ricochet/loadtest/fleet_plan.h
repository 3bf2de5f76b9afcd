#pragma once
/// Which server each bot of a step goes to: round robin over the servers listed, bot k (0-based,
/// over the whole run) to server k % servers, so every server gets its share of each step and
/// of the ramp. A load test whose bots are placed by the servers (--find-match) plans every bot
/// to the first server (servers = 1), which then places it; the scrapes stay on every server.

#include <cstddef>
#include <vector>

namespace ricochet::loadtest {

/// The bots of one step that go to one server.
struct FleetPlan {
  std::size_t server = 0;  ///< index in LoadTestConfig::servers
  std::vector<int> bots;   ///< the bots' indices over the whole run, increasing
};

/// Bots first..first + count - 1 over `servers` (≥ 1) servers; one plan per server that gets a
/// bot, in server order.
std::vector<FleetPlan> plan_fleets(int first, int count, std::size_t servers);

}  // namespace ricochet::loadtest
