#include "ricochet/loadtest/capacity.h"

#include <gtest/gtest.h>

#include <vector>

namespace ricochet::loadtest::capacity_test {
namespace {

/// A step that meets every criterion with nothing to spare: each field sits on its threshold.
StepSummary step_on_the_thresholds() {
  StepSummary step;
  step.bots = 1300;
  step.bots_connected = 1300;
  step.measured_s = 30;
  step.server_tick.p99_ms = 4.0;
  step.server_tick.max_ms = 50.0;  // the max is not a criterion: one slow tick in 600 is allowed
  step.overruns = 0;
  step.snapshot_loss = 0.01;
  step.server_cpu_percent = 89.99;
  return step;
}

TEST(CapacityTest, TheThresholdsAreTheDocumentedOnes) {
  EXPECT_EQ(kCapacityCriteria.max_tick_p99_ms, 4.0);
  EXPECT_EQ(kCapacityCriteria.max_overruns, 0);
  EXPECT_EQ(kCapacityCriteria.max_snapshot_loss, 0.01);
  EXPECT_EQ(kCapacityCriteria.server_cpu_percent_below, 90);
}

TEST(CapacityTest, AStepOnEveryThresholdMeetsCapacity) {
  const StepSummary step = step_on_the_thresholds();
  EXPECT_TRUE(capacity_shortfalls(step).empty());
  EXPECT_TRUE(step.meets_capacity());
}

TEST(CapacityTest, EachCriterionFailsOnItsOwn) {
  const auto missed = [](void (*change)(StepSummary&)) {
    StepSummary step = step_on_the_thresholds();
    change(step);
    EXPECT_FALSE(step.meets_capacity());
    return capacity_shortfalls(step);
  };
  using S = CapacityShortfall;
  EXPECT_EQ(missed([](StepSummary& s) { s.measured_s = 0; }), std::vector{S::NotMeasured});
  EXPECT_EQ(missed([](StepSummary& s) { s.bots_connected = 1299; }), std::vector{S::BotsMissing});
  EXPECT_EQ(missed([](StepSummary& s) { s.server_tick.p99_ms = 4.001; }), std::vector{S::TickP99});
  EXPECT_EQ(missed([](StepSummary& s) { s.overruns = 1; }), std::vector{S::Overruns});
  EXPECT_EQ(missed([](StepSummary& s) { s.snapshot_loss = 0.0101; }), std::vector{S::SnapshotLoss});
  EXPECT_EQ(missed([](StepSummary& s) { s.server_cpu_percent = 90; }), std::vector{S::ServerCpu});
}

TEST(CapacityTest, ThePercentileThatCountsIsTheP99NotTheP95OrTheMax) {
  StepSummary step = step_on_the_thresholds();
  step.server_tick.p95_ms = 3.0;
  step.server_tick.p99_ms = 5.0;
  EXPECT_EQ(capacity_shortfalls(step), std::vector{CapacityShortfall::TickP99});
  step.server_tick.p99_ms = 1.0;
  step.server_tick.max_ms = 100.0;
  EXPECT_TRUE(step.meets_capacity());
}

TEST(CapacityTest, EveryMissIsListedInOrder) {
  StepSummary step;  // nothing measured
  step.bots = 10;
  step.server_tick.p99_ms = 9;
  step.overruns = 2;
  step.snapshot_loss = 0.5;
  step.server_cpu_percent = 99;
  using S = CapacityShortfall;
  EXPECT_EQ(capacity_shortfalls(step), (std::vector{S::NotMeasured, S::BotsMissing, S::TickP99,
                                                    S::Overruns, S::SnapshotLoss, S::ServerCpu}));
  EXPECT_STREQ(name(S::TickP99), "tick_p99");
  EXPECT_STREQ(name(S::ServerCpu), "server_cpu");
}

TEST(CapacityTest, CriteriaCanBeTightened) {
  CapacityCriteria strict;
  strict.max_tick_p99_ms = 1.0;
  EXPECT_EQ(capacity_shortfalls(step_on_the_thresholds(), strict),
            std::vector{CapacityShortfall::TickP99});
}

TEST(CapacityTest, TheGeneratorIsSaturatedFromNinetyPercent) {
  StepSummary step;
  step.generator_cpu_percent = 89.9;
  EXPECT_FALSE(step.generator_saturated());
  step.generator_cpu_percent = kGeneratorSaturatedCpuPercent;
  EXPECT_TRUE(step.generator_saturated());
}

}  // namespace
}  // namespace ricochet::loadtest::capacity_test
