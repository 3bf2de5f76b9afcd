#include <gtest/gtest.h>

#include "ricochet/proto/reliable_channel.h"

namespace ricochet::proto::reliable_test {
namespace {

std::vector<std::uint8_t> bytes(std::uint8_t value, std::size_t size = 3) {
  return std::vector<std::uint8_t>(size, value);
}

TEST(ReliableSender, SendsOnceThenResendsOnlyAfterTheIntervalUntilAcked) {
  ReliableSender sender(16, 16);
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
  ReliableSender sender(2, 2);
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

TEST(ReliableSender, DroppableMessagesStopAtHalfTheWindowMustArriveOnesWaitBehindIt) {
  ReliableSender sender(4, 6);
  ASSERT_TRUE(sender.push(bytes(0), Delivery::Droppable));
  ASSERT_TRUE(sender.push(bytes(1), Delivery::Droppable));
  EXPECT_FALSE(sender.push(bytes(9), Delivery::Droppable)) << "half the window of 4 is queued";
  for (std::uint8_t i = 2; i < 6; ++i) ASSERT_TRUE(sender.push(bytes(i), Delivery::MustArrive));
  EXPECT_FALSE(sender.push(bytes(9), Delivery::MustArrive)) << "max_queued 6";
  // Only the window's four go out: the receiver would refuse ids further ahead.
  auto first = sender.take_due(0, 100, 1000);
  ASSERT_EQ(first.size(), 4u);
  EXPECT_EQ(first.back().id, 3);
  EXPECT_FALSE(sender.has_due(1, 100));
  sender.acknowledge(0);
  sender.acknowledge(1);
  EXPECT_TRUE(sender.has_due(1, 100)) << "the acks made room for the waiting two";
  auto rest = sender.take_due(1, 100, 1000);
  ASSERT_EQ(rest.size(), 2u);
  EXPECT_EQ(rest[0].id, 4);
  EXPECT_EQ(rest[1].bytes, bytes(5));
  EXPECT_EQ(sender.resends(), 0u);
  // Ids stay consecutive: a refused message took none.
  ReliableReceiver receiver;
  std::vector<std::uint8_t> out;
  for (const auto& message : first) receiver.receive(message);
  for (const auto& message : rest) receiver.receive(message);
  for (std::uint8_t i = 0; i < 6; ++i) {
    ASSERT_TRUE(receiver.pop(out));
    EXPECT_EQ(out, bytes(i));
  }
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
  ReliableSender sender(8, 8);
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
}  // namespace ricochet::proto::reliable_test
