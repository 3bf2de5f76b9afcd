#include <gtest/gtest.h>

#include <random>
#include <set>

#include "ricochet/proto/ack_window.h"
#include "ricochet/proto/replay_window.h"

namespace ricochet::proto::replay_test {
namespace {

TEST(ReplayWindow, AcceptsEachSequenceOnceInAnyOrderWithin256) {
  ReplayWindow window;
  EXPECT_FALSE(window.already_received(0));
  for (std::uint64_t sequence : {5u, 3u, 9u, 4u}) {
    EXPECT_FALSE(window.already_received(sequence));
    window.mark_received(sequence);
    EXPECT_TRUE(window.already_received(sequence));
  }
  EXPECT_FALSE(window.already_received(6));
  window.mark_received(1000);
  EXPECT_TRUE(window.already_received(1000 - 256)) << "too old to tell: refused";
  EXPECT_FALSE(window.already_received(1000 - 255));
  EXPECT_TRUE(window.already_received(9));
}

TEST(ReplayWindow, CountsTheSequencesBelowTheNewestThatNeverCameAndThoseThatCameLate) {
  ReplayWindow window;
  // 0 lost; 1, 2; 3 and 4 lost; 6 before 5; 5 late; 8, then 7 late.
  window.mark_received(1);
  EXPECT_EQ(window.missing(), 1u) << "sequences start at 0";
  window.mark_received(2);
  window.mark_received(6);
  EXPECT_EQ(window.missing(), 4u);
  window.mark_received(5);
  window.mark_received(8);
  window.mark_received(7);
  EXPECT_EQ(window.missing(), 3u);  // 0, 3, 4
  EXPECT_EQ(window.late(), 2u);     // 5, 7
  EXPECT_EQ(window.newest(), 8u);
}

TEST(ReplayWindow, AckHeaderNamesTheNewestAndTheBitsBehindIt) {
  ReplayWindow window;
  for (std::uint64_t sequence : {70000u, 69999u, 69997u, 69968u}) window.mark_received(sequence);
  const AckHeader ack = window.ack_header();
  EXPECT_EQ(ack.ack, static_cast<std::uint16_t>(70000));
  EXPECT_EQ(ack.ack_bits, (1u << 0) | (1u << 2) | (1u << 31));
}

TEST(ReplayWindow, AgreesWithASetOfEverySequenceAcceptedUnderJumpsReorderingAndReplays) {
  // The window is a bitmap that slides with the newest sequence; the model keeps every sequence.
  ReplayWindow window;
  std::set<std::uint64_t> accepted;
  std::mt19937_64 random(7);
  std::uint64_t next = 0;
  for (int step = 0; step < 20000; ++step) {
    std::uint64_t sequence = next;
    switch (random() % 6) {
      case 0:
        sequence = next + random() % 300;
        break;  // a jump, at times past 256
      case 1:
        sequence = next > 300 ? next - random() % 300 : 0;
        break;  // late or replayed
      default:
        break;
    }
    next = std::max(next, sequence + 1);
    const std::uint64_t newest = accepted.empty() ? 0 : *accepted.rbegin();
    const bool expected = !accepted.empty() && sequence <= newest &&
                          (newest - sequence >= ReplayWindow::kSize || accepted.contains(sequence));
    ASSERT_EQ(window.already_received(sequence), expected) << "step " << step;
    if (!expected) {
      window.mark_received(sequence);
      accepted.insert(sequence);
    }
    AckHeader ack;
    ack.ack = static_cast<std::uint16_t>(*accepted.rbegin());
    for (std::uint64_t i = 0; i < 32 && i < *accepted.rbegin(); ++i) {
      if (accepted.contains(*accepted.rbegin() - 1 - i)) ack.ack_bits |= 1u << i;
    }
    ASSERT_EQ(window.ack_header(), ack) << "step " << step;
  }
}

TEST(SentPacketWindow, AcksRepeatedByManyPacketsAcknowledgeEachPacketOnce) {
  SentPacketWindow sent;
  std::vector<std::uint16_t> ids;
  std::vector<std::uint16_t> expected;
  for (std::uint64_t sequence = 0; sequence < 1000; ++sequence) {
    sent.on_sent(sequence, static_cast<TimeUs>(sequence), {static_cast<std::uint16_t>(sequence)});
    if (sequence % 5 == 3) continue;  // never acked
    expected.push_back(static_cast<std::uint16_t>(sequence));
    // The peer acks this one and repeats the fates of the 32 before it.
    AckHeader ack{static_cast<std::uint16_t>(sequence), 0};
    for (std::uint64_t i = 0; i < 32 && i < sequence; ++i) {
      if ((sequence - 1 - i) % 5 != 3) ack.ack_bits |= 1u << i;
    }
    sent.on_ack(ack, sequence + 1, static_cast<TimeUs>(sequence) + 100, ids);
  }
  EXPECT_EQ(ids, expected);
  EXPECT_EQ(sent.rtt_us(), 100);
  EXPECT_TRUE(sent.acked(999));
  EXPECT_FALSE(sent.acked(998));
  sent.on_sent(999 + SentPacketWindow::kSize, 0, {});  // a later packet takes 999's slot
  EXPECT_FALSE(sent.acked(999)) << "a slot reused by a later packet no longer answers";
}

TEST(SentPacketWindow, AckAcrossThe16BitWrapAcknowledgesTheRightPackets) {
  SentPacketWindow sent;
  const std::uint64_t first = 65530;
  for (std::uint64_t sequence = first; sequence < first + 10; ++sequence) {
    sent.on_sent(sequence, 0, {static_cast<std::uint16_t>(sequence - first)});
  }
  std::vector<std::uint16_t> ids;
  // Peer received 65539 (low 16 bits: 3) and 65537 (bit 1), not 65538.
  sent.on_ack({3, 0b10}, first + 10, 1000, ids);
  EXPECT_TRUE(sent.acked(65539));
  EXPECT_TRUE(sent.acked(65537));
  EXPECT_FALSE(sent.acked(65538));
  EXPECT_EQ(ids, (std::vector<std::uint16_t>{9, 7}));
  EXPECT_EQ(sent.rtt_us(), 1000);
  ids.clear();
  sent.on_ack({3, 0b10}, first + 10, 2000, ids);
  EXPECT_TRUE(ids.empty()) << "acked once only";
}

// Entries keep the low 32 bits of the send time: a round trip across a multiple of 2^32 µs
// (every 71 minutes of uptime) still measures what it took.
TEST(SentPacketWindow, RoundTripAcrossThe32BitClockWrapIsExact) {
  SentPacketWindow sent;
  const TimeUs sent_at = (TimeUs{1} << 32) * 3 - 40;
  sent.on_sent(7, sent_at, {});
  std::vector<std::uint16_t> ids;
  sent.on_ack({7, 0}, 8, sent_at + 100, ids);
  EXPECT_TRUE(sent.acked(7));
  EXPECT_EQ(sent.rtt_us(), 100);
}

// The reliable messages of a packet pushed out of the window unacked are not reported by any
// later ack (the resender sends them again); those of packets in the window are, once each.
TEST(SentPacketWindow, ReliableIdsLeaveWithTheirPacketsWindow) {
  SentPacketWindow sent;
  sent.on_sent(0, 0, {11});
  sent.on_sent(1, 0, {12, 13});
  for (std::uint64_t sequence = 2; sequence < 2 + SentPacketWindow::kSize; ++sequence) {
    sent.on_sent(sequence, 0, {});
  }
  std::vector<std::uint16_t> ids;
  const std::uint64_t next = 2 + SentPacketWindow::kSize;
  sent.on_ack({static_cast<std::uint16_t>(next - 1), 0xFFFFFFFF}, next, 10, ids);
  EXPECT_TRUE(ids.empty()) << "packets 0 and 1 left the window";
  sent.on_sent(next, 0, {21});
  sent.on_sent(next + 1, 0, {22});
  sent.on_ack({static_cast<std::uint16_t>(next + 1), 0b1}, next + 2, 20, ids);
  EXPECT_EQ(ids, (std::vector<std::uint16_t>{22, 21}));
}

TEST(SentPacketWindow, AckOfASequenceNeverSentIsIgnored) {
  SentPacketWindow sent;
  std::vector<std::uint16_t> ids;
  sent.on_ack({0, 0xFFFFFFFF}, 0, 0, ids);
  sent.on_sent(0, 0, {1});
  sent.on_ack({5, 0xFFFFFFFF}, 1, 0, ids);
  EXPECT_TRUE(ids.empty());
  EXPECT_FALSE(sent.acked(0));
}

}  // namespace
}  // namespace ricochet::proto::replay_test
