// Every counted enum of proto: its count is one past its last named enumerator.

#include "enum_count.h"

#include "ricochet/proto/control_client.h"
#include "ricochet/proto/control_states.h"
#include "ricochet/proto/frame.h"
#include "ricochet/proto/packet.h"
#include "ricochet/proto/transport_counters.h"

namespace ricochet::proto::enum_count_test {
namespace {

using ricochet::test::expect_counted;

TEST(EnumCountTest, TransportCounters) {
  expect_counted<DropReason>(kDropReasonCount, [](DropReason r) { return name(r); });
  expect_counted<DisconnectReason>(kDisconnectReasonCount,
                                   [](DisconnectReason r) { return name(r); });
  expect_counted<ConnectionState>(kConnectionStateCount, [](ConnectionState s) { return name(s); });
}

TEST(EnumCountTest, Packets) {
  expect_counted<PacketType>(kPacketTypeCount, [](PacketType t) { return name(t); });
}

TEST(EnumCountTest, ControlChannel) {
  expect_counted<FrameRefusal>(kFrameRefusalCount, [](FrameRefusal r) { return name(r); });
  expect_counted<ControlState>(kControlStateCount, [](ControlState s) { return name(s); });
  expect_counted<ClientMessageKind>(kClientMessageKindCount,
                                    [](ClientMessageKind k) { return name(k); });
  expect_counted<RequestRefusal>(kRequestRefusalCount, [](RequestRefusal r) { return name(r); });
  expect_counted<ControlCloseReason>(kControlCloseReasonCount,
                                     [](ControlCloseReason r) { return name(r); });
}

}  // namespace
}  // namespace ricochet::proto::enum_count_test
