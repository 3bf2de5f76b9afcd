// Error codes (result.h): every code has its own stable name, so logs and counters can tell a
// locked database from a full queue and a lack of memory from a disk failure.

#include "ricochet/db/result.h"

#include <gtest/gtest.h>

#include "enum_count.h"

namespace ricochet::db::result_test {
namespace {

TEST(DbErrorCode, EveryCodeHasItsOwnName) {
  ricochet::test::expect_counted<DbErrorCode>(kDbErrorCodeCount,
                                              [](DbErrorCode c) { return to_string(c); });
  EXPECT_STREQ(to_string(DbErrorCode::Busy), "busy");
  EXPECT_STREQ(to_string(DbErrorCode::Unavailable), "unavailable");
  EXPECT_STREQ(to_string(DbErrorCode::QueueFull), "queue_full");
  EXPECT_STREQ(to_string(DbErrorCode::Storage), "storage");
  EXPECT_STREQ(to_string(DbErrorCode::OutOfMemory), "out_of_memory");
}

}  // namespace
}  // namespace ricochet::db::result_test
