#pragma once
/// Who takes a soak's bot slot next and for how long, sans-IO and seeded: slot k's first bot
/// signs in as <prefix>-<k>; each later one as the slot's last account, or with
/// ChurnConfig::new_account_share as a new one, <prefix>-<k>.<n>; each stays a lifetime drawn
/// uniformly from [min_life_s, max_life_s].

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "ricochet/loadtest/soak_config.h"

namespace ricochet::loadtest {

struct Incarnation {
  std::string account;
  bool new_account = false;  ///< the account's first use in this run (registered when new)
  double life_s = 0;         ///< 0: stays for the whole run (churn inactive)
};

class ChurnPlan {
 public:
  /// `churn` must be valid; slots are 1..`slots`.
  ChurnPlan(const ChurnConfig& churn, std::string prefix, int slots, std::uint64_t seed);

  /// The next bot of `slot` (1..slots).
  Incarnation next(int slot);

 private:
  ChurnConfig churn_;
  std::string prefix_;
  std::mt19937_64 random_;
  std::vector<int> accounts_;  ///< per slot: accounts used so far (0: the slot has not started)
};

}  // namespace ricochet::loadtest
