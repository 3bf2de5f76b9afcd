// Error codes (result.h): every code has its own stable name, so logs and counters can tell a
// locked database from a full queue and a lack of memory from a disk failure.

#include "ricochet/db/result.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace ricochet::db {
namespace {

TEST(DbErrorCode, EveryCodeHasItsOwnName) {
  std::set<std::string> names;
  for (int i = 0; i < kDbErrorCodeCount; ++i) {
    const std::string name = to_string(static_cast<DbErrorCode>(i));
    EXPECT_NE(name, "unknown") << "code " << i << " has no name";
    EXPECT_TRUE(names.insert(name).second) << "two codes are named " << name;
  }
  EXPECT_STREQ(to_string(DbErrorCode::Busy), "busy");
  EXPECT_STREQ(to_string(DbErrorCode::QueueFull), "queue_full");
  EXPECT_STREQ(to_string(DbErrorCode::Storage), "storage");
  EXPECT_STREQ(to_string(DbErrorCode::OutOfMemory), "out_of_memory");
}

}  // namespace
}  // namespace ricochet::db
