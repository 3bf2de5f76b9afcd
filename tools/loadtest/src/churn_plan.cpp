#include "ricochet/loadtest/churn_plan.h"

namespace ricochet::loadtest {

ChurnPlan::ChurnPlan(const ChurnConfig& churn, std::string prefix, int slots, std::uint64_t seed)
    : churn_(churn),
      prefix_(std::move(prefix)),
      random_(seed),
      accounts_(static_cast<std::size_t>(slots), 0) {}

Incarnation ChurnPlan::next(int slot) {
  int& used = accounts_.at(static_cast<std::size_t>(slot - 1));
  Incarnation out;
  out.new_account = used == 0;
  if (!out.new_account && churn_.active()) {
    out.new_account = std::bernoulli_distribution(churn_.new_account_share)(random_);
  }
  if (out.new_account) ++used;
  out.account = prefix_;
  out.account += '-';
  out.account += std::to_string(slot);
  if (used > 1) {
    out.account += '.';
    out.account += std::to_string(used - 1);
  }
  if (churn_.active()) {
    out.life_s =
        std::uniform_real_distribution<double>(churn_.min_life_s, churn_.max_life_s)(random_);
  }
  return out;
}

}  // namespace ricochet::loadtest
