#include "ricochet/bot/input_history.h"

#include <gtest/gtest.h>

namespace ricochet::bot::input_history_test {
namespace {

TEST(InputHistory, NumbersFromOneAndSendsTheNewestFewOldestFirst) {
  InputHistory history;
  for (int i = 0; i < 6; ++i) history.push({});
  wire::ClientPayload payload;
  history.fill(payload);
  ASSERT_EQ(payload.inputs_size(), static_cast<int>(InputHistory::kPerPayload));
  EXPECT_EQ(payload.inputs(0).sequence(), 3u);
  EXPECT_EQ(payload.inputs(3).sequence(), 6u);
  EXPECT_EQ(history.last_sequence(), 6u);
}

TEST(InputHistory, AcknowledgementDropsAppliedInputsAndIgnoresUnsentOnes) {
  InputHistory history;
  for (int i = 0; i < 5; ++i) history.push({});
  EXPECT_TRUE(history.acknowledge(3));
  ASSERT_EQ(history.unacknowledged().size(), 2u);
  EXPECT_EQ(history.unacknowledged().front().sequence(), 4u);
  EXPECT_TRUE(history.acknowledge(2));  // older: changes nothing
  EXPECT_EQ(history.unacknowledged().size(), 2u);
  EXPECT_FALSE(history.acknowledge(9));  // never sent: untrusted, ignored
  EXPECT_EQ(history.acknowledged(), 3u);
  EXPECT_TRUE(history.acknowledge(0));  // nothing applied yet is valid too
}

TEST(InputHistory, KeepsABoundedNumberUnacknowledged) {
  InputHistory history;
  for (std::size_t i = 0; i < 3 * InputHistory::kMaxKept; ++i) history.push({});
  EXPECT_EQ(history.unacknowledged().size(), InputHistory::kMaxKept);
}

}  // namespace
}  // namespace ricochet::bot::input_history_test
