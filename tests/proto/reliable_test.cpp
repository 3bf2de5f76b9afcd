#include <gtest/gtest.h>

#include "ricochet/proto/reliable_channel.h"

namespace ricochet::proto {
namespace {

std::vector<std::uint8_t> bytes(std::uint8_t value, std::size_t size = 3) {
  return std::vector<std::uint8_t>(size, value);
}

TEST(ReliableSender, SendsOnceThenResendsOnlyAfterTheIntervalUntilAcked) {
  ReliableSender sender(16);
  ASSERT_TRUE(sender.push(bytes(1)));
  ASSERT_TRUE(sender.push(bytes(2)));
  auto first = sender.take_due(0, 100, 1000);
  ASSERT_EQ(first.size(), 2u);
  EXPECT_EQ(first[0].id, 0);
  EXPECT_EQ(first[1].bytes, bytes(2));
  EXPECT_TRUE(sender.take_due(99, 100, 1000).empty());
  sender.acknowledge(0);
  auto again = sender.take_due(100, 100, 1000);
  ASSERT_EQ(again.size(), 1u);
  EXPECT_EQ(again[0].id, 1);
  EXPECT_EQ(sender.resends(), 1u);
  sender.acknowledge(1);
  EXPECT_EQ(sender.pending(), 0u);
  EXPECT_FALSE(sender.has_due(10'000, 100));
}

TEST(ReliableSender, RespectsTheByteBudgetInOrderAndTheCap) {
  ReliableSender sender(2);
  ASSERT_TRUE(sender.push(bytes(1, 10)));
  ASSERT_TRUE(sender.push(bytes(2, 10)));
  EXPECT_FALSE(sender.push(bytes(3))) << "cap of 2 pending";
  auto some = sender.take_due(0, 100, kReliableMessageHeaderBytes + 10);
  ASSERT_EQ(some.size(), 1u);
  EXPECT_EQ(some[0].id, 0);
  sender.acknowledge(1);  // out of order ack: 0 still pending
  EXPECT_EQ(sender.pending(), 2u);
  sender.acknowledge(0);
  EXPECT_EQ(sender.pending(), 0u);
  sender.acknowledge(0);  // a late duplicate ack does nothing
  EXPECT_TRUE(sender.push(bytes(4)));
}

TEST(ReliableReceiver, DeliversInOrderOnceAndRefusesFarAhead) {
  ReliableReceiver receiver;
  std::vector<std::uint8_t> out;
  EXPECT_EQ(receiver.receive({1, bytes(1)}), ReliableReceiver::Outcome::Accepted);
  EXPECT_FALSE(receiver.pop(out)) << "0 missing";
  EXPECT_EQ(receiver.receive({0, bytes(0)}), ReliableReceiver::Outcome::Accepted);
  EXPECT_EQ(receiver.receive({0, bytes(0)}), ReliableReceiver::Outcome::Duplicate);
  ASSERT_TRUE(receiver.pop(out));
  EXPECT_EQ(out, bytes(0));
  ASSERT_TRUE(receiver.pop(out));
  EXPECT_EQ(out, bytes(1));
  EXPECT_FALSE(receiver.pop(out));
  EXPECT_EQ(receiver.receive({0, bytes(0)}), ReliableReceiver::Outcome::Duplicate);
  EXPECT_EQ(receiver.receive({2 + ReliableReceiver::kWindow, bytes(9)}),
            ReliableReceiver::Outcome::OutOfWindow);
}

TEST(ReliableChannel, IdsWrapAround16Bits) {
  ReliableSender sender(8);
  ReliableReceiver receiver;
  std::vector<std::uint8_t> out;
  for (int i = 0; i < 70000; ++i) {
    ASSERT_TRUE(sender.push(bytes(static_cast<std::uint8_t>(i))));
    auto due = sender.take_due(i, 100, 2000);
    ASSERT_EQ(due.size(), 1u);
    ASSERT_EQ(receiver.receive(due[0]), ReliableReceiver::Outcome::Accepted) << i;
    ASSERT_TRUE(receiver.pop(out));
    ASSERT_EQ(out, bytes(static_cast<std::uint8_t>(i)));
    sender.acknowledge(due[0].id);
  }
}

}  // namespace
}  // namespace ricochet::proto
