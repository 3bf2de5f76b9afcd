// Every counted enum of the server: its count is one past its last named enumerator.

#include "enum_count.h"

#include "admin_http.h"
#include "agones_sdk.h"
#include "control_counters.h"
#include "match_registry.h"
#include "ricochet/server/combat.h"
#include "ricochet/server/input_buffer.h"
#include "ricochet/server/match.h"
#include "ricochet/server/weapons.h"
#include "server.h"

namespace ricochet::server::enum_count_test {
namespace {

using ricochet::test::expect_counted;

TEST(EnumCountTest, Match) {
  expect_counted<JoinRefusal>(kJoinRefusalCount, [](JoinRefusal r) { return name(r); });
  expect_counted<ChatDrop>(kChatDropCount, [](ChatDrop d) { return name(d); });
  expect_counted<InputDrop>(kInputDropCount, [](InputDrop d) { return name(d); });
  expect_counted<Violation>(kViolationCount, [](Violation v) { return name(v); });
  expect_counted<WeaponKind>(kWeaponCount, [](WeaponKind k) { return name(k); });
}

TEST(EnumCountTest, Network) {
  expect_counted<ControlRefusal>(kControlRefusalCount, [](ControlRefusal r) { return name(r); });
  expect_counted<AdminRejectReason>(kAdminRejectReasonCount,
                                    [](AdminRejectReason r) { return name(r); });
  expect_counted<SeatRefusal>(kSeatRefusalCount, [](SeatRefusal r) { return name(r); });
  expect_counted<AgonesCall>(kAgonesCallCount, [](AgonesCall c) { return name(c); });
  expect_counted<AgonesOutcome>(kAgonesOutcomeCount, [](AgonesOutcome o) { return name(o); });
  expect_counted<LiveRefusal>(kLiveRefusalCount, [](LiveRefusal r) { return name(r); });
}

}  // namespace
}  // namespace ricochet::server::enum_count_test
