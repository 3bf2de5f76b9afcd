#include "ricochet/loadtest/churn_plan.h"

#include <gtest/gtest.h>

#include <set>

#include "ricochet/bot/bot_config.h"

namespace ricochet::loadtest::churn_plan_test {
namespace {

TEST(ChurnPlan, EachSlotStartsOnItsOwnAccountAndStaysWithinTheLives) {
  ChurnConfig churn;
  churn.min_life_s = 20;
  churn.max_life_s = 50;
  ChurnPlan plan(churn, "soak", 3, 7);
  for (int slot = 1; slot <= 3; ++slot) {
    const Incarnation first = plan.next(slot);
    EXPECT_EQ(first.account, "soak-" + std::to_string(slot));
    EXPECT_TRUE(first.new_account);
    EXPECT_GE(first.life_s, 20);
    EXPECT_LE(first.life_s, 50);
  }
}

TEST(ChurnPlan, ReturningBotsReuseTheSlotsAccountOrTakeANewOneAtTheShare) {
  ChurnConfig churn;
  churn.min_life_s = 60;
  churn.max_life_s = 600;
  churn.new_account_share = 0.25;
  ChurnPlan plan(churn, "soak", 1, 11);
  std::string last = plan.next(1).account;
  std::set<std::string> accounts{last};
  int fresh = 0;
  constexpr int kReturns = 4000;
  for (int i = 0; i < kReturns; ++i) {
    const Incarnation next = plan.next(1);
    EXPECT_TRUE(bot::valid_account_name(next.account)) << next.account;
    if (next.new_account) {
      ++fresh;
      EXPECT_TRUE(accounts.insert(next.account).second) << next.account;
    } else {
      EXPECT_EQ(next.account, last);  // the same account signs in again
    }
    last = next.account;
  }
  EXPECT_NEAR(static_cast<double>(fresh) / kReturns, 0.25, 0.03);
  EXPECT_EQ(accounts.size(), static_cast<std::size_t>(fresh) + 1);
}

TEST(ChurnPlan, TheSameSeedGivesTheSamePlan) {
  ChurnConfig churn;
  ChurnPlan a(churn, "soak", 2, 5);
  ChurnPlan b(churn, "soak", 2, 5);
  for (int i = 0; i < 50; ++i) {
    const Incarnation x = a.next(1 + i % 2);
    const Incarnation y = b.next(1 + i % 2);
    EXPECT_EQ(x.account, y.account);
    EXPECT_EQ(x.life_s, y.life_s);
  }
}

TEST(ChurnPlan, WithoutChurnABotStaysForTheWholeRun) {
  ChurnConfig churn;
  churn.max_life_s = 0;
  ChurnPlan plan(churn, "soak", 1, 1);
  EXPECT_EQ(plan.next(1).life_s, 0);
  const Incarnation again = plan.next(1);
  EXPECT_EQ(again.account, "soak-1");
  EXPECT_FALSE(again.new_account);
}

}  // namespace
}  // namespace ricochet::loadtest::churn_plan_test
