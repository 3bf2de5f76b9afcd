#pragma once
/// One test's database on either backend, for the tests of the Store contract and the rules above
/// it, which run against both (TEST_P over kBackends): a fresh SQLite file in a temp directory,
/// or a fresh database on this process's PostgreSQL cluster (postgres_cluster.h). Raw access
/// beside the store (a query, a failure injected with a trigger, another server's write lock)
/// goes through a connection of its own, as another process's would.

#include <gtest/gtest.h>
#include <libpq-fe.h>
#include <sqlite3.h>

#include <memory>
#include <stdexcept>
#include <string>

#include "db_test_util.h"
#include "postgres_cluster.h"
#include "postgres_handle.h"
#include "ricochet/db/store.h"
#include "sqlite_handle.h"

namespace ricochet::db::test {

enum class Backend { Sqlite, Postgres };

inline const auto kBackends = ::testing::Values(Backend::Sqlite, Backend::Postgres);

/// "Sqlite" / "Postgres": the suffix of a parametrised test's name.
inline std::string backend_name(const ::testing::TestParamInfo<Backend>& info) {
  return info.param == Backend::Sqlite ? "Sqlite" : "Postgres";
}

class TestDatabase {
 public:
  explicit TestDatabase(Backend backend) : backend_(backend) {
    url_or_path_ = backend == Backend::Sqlite
                       ? dir_.file("ricochet.db")
                       : ricochet::test::PostgresCluster::shared().create_database();
  }

  Backend backend() const { return backend_; }
  bool postgres() const { return backend_ == Backend::Postgres; }
  /// The SQLite file's path or the PostgreSQL URL.
  const std::string& url_or_path() const { return url_or_path_; }
  /// How the store's error messages name the database.
  std::string where() const {
    return postgres() ? postgres::describe_url(url_or_path_) : url_or_path_;
  }
  /// The temp directory (SQLite's file is in it; other files may go there too).
  const TempDir& dir() const { return dir_; }

  DbResult<std::unique_ptr<Store>> try_open(int busy_timeout_ms = 5000) const {
    return open_store({.url_or_path = url_or_path_, .busy_timeout_ms = busy_timeout_ms});
  }
  /// Another store (connection) on the database, as another server process would have.
  std::unique_ptr<Store> open(int busy_timeout_ms = 5000) const {
    return must(try_open(busy_timeout_ms), "open_store");
  }

  /// The first column of the first row of `sql` as text ("" when there is no row), through a
  /// connection of its own.
  std::string query_one(const std::string& sql) const {
    if (postgres()) {
      postgres::Connection raw = connect();
      postgres::Result r = postgres::exec(raw.get(), sql.c_str());
      if (!r.ok()) throw std::runtime_error(sql + ": " + PQresultErrorMessage(r.get()));
      if (r.rows() == 0) return "";
      constexpr Oid kBytea = 17;  // the bytes themselves, as SQLite's blob gives them
      if (PQftype(r.get(), 0) != kBytea) return r.text(0, 0);
      std::size_t length = 0;
      unsigned char* bytes = PQunescapeBytea(
          reinterpret_cast<const unsigned char*>(PQgetvalue(r.get(), 0, 0)), &length);
      std::string out(reinterpret_cast<const char*>(bytes), length);
      PQfreemem(bytes);
      return out;
    }
    sqlite::Connection raw;
    std::string out;
    if (sqlite::open(url_or_path_, SQLITE_OPEN_READONLY, raw) != SQLITE_OK)
      throw std::runtime_error("cannot open " + url_or_path_);
    sqlite3_stmt* stmt = nullptr;
    if (sqlite3_prepare_v2(raw.get(), sql.c_str(), -1, &stmt, nullptr) != SQLITE_OK)
      throw std::runtime_error(sql + ": " + sqlite3_errmsg(raw.get()));
    if (sqlite3_step(stmt) == SQLITE_ROW) {
      const auto* bytes = static_cast<const char*>(sqlite3_column_blob(stmt, 0));
      out.assign(bytes ? bytes : "", static_cast<std::size_t>(sqlite3_column_bytes(stmt, 0)));
    }
    sqlite3_finalize(stmt);
    return out;
  }
  std::int64_t raw_integer(const std::string& sql) const { return std::stoll(query_one(sql)); }

  /// Runs SQL without results through a connection of its own; throws when it fails.
  void exec(const std::string& sql) const {
    if (postgres()) {
      postgres::Connection raw = connect();
      postgres::Result r = postgres::exec(raw.get(), sql.c_str());
      if (!r.ok()) throw std::runtime_error(sql + ": " + PQresultErrorMessage(r.get()));
      return;
    }
    sqlite::Connection raw;
    if (sqlite::open(url_or_path_, SQLITE_OPEN_READWRITE, raw) != SQLITE_OK ||
        sqlite::exec(raw.get(), sql.c_str()) != SQLITE_OK)
      throw std::runtime_error(sql + ": " + sqlite3_errmsg(raw.get()));
  }

  /// Makes every row write matching `event` (a trigger event such as "BEFORE DELETE ON
  /// sessions") and `condition` (SQL over NEW/OLD, empty for every row) fail with "injected
  /// failure", so that a compound write can be failed half-way.
  void inject_failure(const std::string& event, const std::string& condition = "") const {
    const std::string when = condition.empty() ? "" : " WHEN (" + condition + ")";
    if (postgres()) {
      exec(
          "CREATE FUNCTION injected_failure() RETURNS trigger LANGUAGE plpgsql AS"
          " $$BEGIN RAISE EXCEPTION 'injected failure'; END$$");
      exec("CREATE TRIGGER injected_failure " + event + " FOR EACH ROW" + when +
           " EXECUTE FUNCTION injected_failure()");
      return;
    }
    exec("CREATE TRIGGER injected_failure " + event + " FOR EACH ROW" + when +
         " BEGIN SELECT RAISE(ABORT, 'injected failure'); END");
  }
  /// Drops what inject_failure made.
  void remove_failure() const {
    if (postgres()) {
      exec("DROP FUNCTION injected_failure() CASCADE");
      return;
    }
    exec("DROP TRIGGER injected_failure");
  }

  /// Another server process's write lock, held until release() or destruction: SQLite's
  /// BEGIN IMMEDIATE, PostgreSQL's advisory lock of Store::transaction.
  class WriteLock {
   public:
    explicit WriteLock(const TestDatabase& db) : postgres_(db.postgres()) {
      if (postgres_) {
        pg_ = db.connect();
        const std::string lock =
            "SELECT pg_advisory_xact_lock(" + std::to_string(postgres::kWriteLockKey) + ")";
        for (const std::string& sql : {std::string("BEGIN"), lock}) {
          postgres::Result r = postgres::exec(pg_.get(), sql.c_str());
          if (!r.ok()) throw std::runtime_error("cannot take the write lock: " + db.where());
        }
        return;
      }
      if (sqlite::open(db.url_or_path(), SQLITE_OPEN_READWRITE, sqlite_) != SQLITE_OK ||
          sqlite::exec(sqlite_.get(), "BEGIN IMMEDIATE") != SQLITE_OK)
        throw std::runtime_error("cannot take the write lock on " + db.url_or_path());
    }
    ~WriteLock() { release(); }
    WriteLock(const WriteLock&) = delete;
    WriteLock& operator=(const WriteLock&) = delete;
    void release() {
      if (pg_) postgres::exec(pg_.get(), "ROLLBACK");
      if (sqlite_) sqlite::exec(sqlite_.get(), "ROLLBACK");
      pg_.reset();
      sqlite_.reset();
    }

   private:
    bool postgres_;
    postgres::Connection pg_;
    sqlite::Connection sqlite_;
  };

  /// A raw PostgreSQL connection to the database (PostgreSQL only).
  postgres::Connection connect() const {
    postgres::Connection raw = postgres::connect(url_or_path_, 5);
    if (PQstatus(raw.get()) != CONNECTION_OK)
      throw std::runtime_error("cannot connect to " + url_or_path_ + ": " +
                               PQerrorMessage(raw.get()));
    return raw;
  }

 private:
  Backend backend_;
  TempDir dir_;
  std::string url_or_path_;
};

}  // namespace ricochet::db::test
