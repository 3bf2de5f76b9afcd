#pragma once
/// Helpers for the db tests: a fresh temporary directory per test (real files, no mocks) and
/// assertions on DbResult / DbStatus that print the error.

#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <stdexcept>
#include <string>

#include "ricochet/db/result.h"
#include "sqlite_handle.h"
#include "temp_dir.h"

namespace ricochet::db::test {

/// A temp directory named ricochet-db-XXXXXX (tests/temp_dir.h).
class TempDir : public ricochet::test::TempDir {
 public:
  TempDir() : ricochet::test::TempDir("ricochet-db") {}
};

inline std::string describe(const DbError& e) {
  return std::string(to_string(e.code)) + ": " + e.message;
}

template <class T>
::testing::AssertionResult fails_with(const DbResult<T>& r, DbErrorCode code) {
  if (r.ok()) return ::testing::AssertionFailure() << "succeeded, expected " << to_string(code);
  if (r.error().code != code)
    return ::testing::AssertionFailure()
           << "failed with " << describe(r.error()) << ", expected " << to_string(code);
  if (r.error().message.empty()) return ::testing::AssertionFailure() << "empty error message";
  return ::testing::AssertionSuccess();
}

inline ::testing::AssertionResult fails_with(const DbStatus& s, DbErrorCode code) {
  if (s.ok()) return ::testing::AssertionFailure() << "succeeded, expected " << to_string(code);
  if (s.error().code != code)
    return ::testing::AssertionFailure()
           << "failed with " << describe(s.error()) << ", expected " << to_string(code);
  if (s.error().message.empty()) return ::testing::AssertionFailure() << "empty error message";
  return ::testing::AssertionSuccess();
}

/// The value of a result that must succeed; fails the test with the error otherwise.
template <class T>
T must(DbResult<T> r, const char* what) {
  if (!r.ok()) throw std::runtime_error(std::string(what) + ": " + describe(r.error()));
  return std::move(r).value();
}

/// Makes every write matching `when` fail (a trigger that RAISEs 'injected failure'), through a
/// raw connection to the file, so that a compound write can be failed half-way. `when` is a
/// trigger event such as "BEFORE DELETE ON sessions".
inline void inject_failure(const std::string& path, const std::string& when) {
  sqlite::Connection raw;
  if (sqlite::open(path, SQLITE_OPEN_READWRITE, raw) != SQLITE_OK)
    throw std::runtime_error("cannot open " + path + " to inject a failure");
  const std::string trigger = "CREATE TRIGGER injected_failure " + when +
                              " BEGIN SELECT RAISE(ABORT, 'injected failure'); END";
  if (sqlite::exec(raw.get(), trigger.c_str()) != SQLITE_OK)
    throw std::runtime_error(trigger + ": " + sqlite3_errmsg(raw.get()));
}

/// Drops the trigger of inject_failure.
inline void remove_failure(const std::string& path) {
  sqlite::Connection raw;
  if (sqlite::open(path, SQLITE_OPEN_READWRITE, raw) != SQLITE_OK ||
      sqlite::exec(raw.get(), "DROP TRIGGER injected_failure") != SQLITE_OK)
    throw std::runtime_error("cannot drop the injected failure in " + path);
}

#define RICOCHET_DB_ASSERT_OK(expr)                                                \
  do {                                                                             \
    const auto& ricochet_db_s = (expr);                                            \
    ASSERT_TRUE(ricochet_db_s.ok())                                                \
        << #expr << ": " << ::ricochet::db::test::describe(ricochet_db_s.error()); \
  } while (0)

#define RICOCHET_DB_EXPECT_OK(expr)                                                \
  do {                                                                             \
    const auto& ricochet_db_s = (expr);                                            \
    EXPECT_TRUE(ricochet_db_s.ok())                                                \
        << #expr << ": " << ::ricochet::db::test::describe(ricochet_db_s.error()); \
  } while (0)

}  // namespace ricochet::db::test
