#pragma once
/// Thin RAII over the SQLite C API: an owned connection, a prepared statement kept for the life
/// of its connection, one use of it (bind in order, step, type-checked column reads, reset when
/// the use ends), a write transaction that rolls back unless committed, and the mapping of SQLite
/// result codes to DbErrorCode.
///
/// Header-only so that the db tests can open raw connections with the same helpers.

#include <sqlite3.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "ricochet/db/result.h"

namespace ricochet::db::sqlite {

struct ConnectionCloser {
  void operator()(sqlite3* db) const { sqlite3_close_v2(db); }
};
/// An open connection. Statements prepared on it must be destroyed first.
using Connection = std::unique_ptr<sqlite3, ConnectionCloser>;

/// Opens `path` with sqlite3_open_v2 `flags`. `out` owns the handle even when opening fails, so
/// that sqlite3_errmsg can still explain the failure; returns the SQLite result code.
inline int open(const std::string& path, int flags, Connection& out) {
  sqlite3* db = nullptr;
  const int rc = sqlite3_open_v2(path.c_str(), &db, flags, nullptr);
  out.reset(db);
  return rc;
}

/// The DbErrorCode for an SQLite result code (primary or extended).
inline DbErrorCode error_code_of(int rc) {
  switch (rc & 0xff) {
    case SQLITE_BUSY:
    case SQLITE_LOCKED:
      return DbErrorCode::Busy;
    case SQLITE_NOTADB:
    case SQLITE_CORRUPT:
      return DbErrorCode::CorruptDatabase;
    case SQLITE_CANTOPEN:
      return DbErrorCode::CannotOpen;
    case SQLITE_NOMEM:
      return DbErrorCode::OutOfMemory;
    default:
      return DbErrorCode::Storage;
  }
}

/// "<path>: <what> failed: <SQLite's message>[: <OS error>]; <what to do>" where there is a fix.
inline DbError error_from(sqlite3* db, int rc, std::string_view path, std::string_view what) {
  const DbErrorCode code = error_code_of(rc);
  std::string message(path);
  message += ": ";
  message += what;
  message += " failed: ";
  message += db && sqlite3_extended_errcode(db) == rc ? sqlite3_errmsg(db) : sqlite3_errstr(rc);
  // The OS error says why a file could not be opened, read or written ("Is a directory").
  const bool os_failure = code == DbErrorCode::CannotOpen || (rc & 0xff) == SQLITE_IOERR;
  if (const int os_error = db ? sqlite3_system_errno(db) : 0; os_failure && os_error != 0) {
    message += ": ";
    message += std::strerror(os_error);
  }
  switch (code) {
    case DbErrorCode::Busy:
      message += "; another process held the lock longer than the busy timeout, retry later";
      break;
    case DbErrorCode::CorruptDatabase:
      message += "; not a Ricochet database, or damaged: restore a backup or move the file away";
      break;
    case DbErrorCode::CannotOpen:
      message += "; check that the directory exists and that the file can be read and written";
      break;
    default:
      break;
  }
  return DbError{code, std::move(message)};
}

/// A prepared statement, finalized on destruction. Prepared once and reused through Query.
class Statement {
 public:
  Statement() = default;
  ~Statement() { sqlite3_finalize(stmt_); }
  Statement(Statement&& other) noexcept : stmt_(other.stmt_) { other.stmt_ = nullptr; }
  Statement& operator=(Statement&& other) noexcept {
    std::swap(stmt_, other.stmt_);
    return *this;
  }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  /// Compiles one SQL statement; returns the SQLite result code.
  int prepare(sqlite3* db, std::string_view sql) {
    sqlite3_finalize(stmt_);
    stmt_ = nullptr;
    return sqlite3_prepare_v3(db, sql.data(), static_cast<int>(sql.size()),
                              SQLITE_PREPARE_PERSISTENT, &stmt_, nullptr);
  }
  sqlite3_stmt* get() const { return stmt_; }

 private:
  sqlite3_stmt* stmt_ = nullptr;
};

/// One execution of a Statement. Parameters are bound in order (?1, ?2, …); text and blobs are
/// bound without copying, so they must outlive the Query. On destruction the statement is reset
/// and unbound, which also ends the read snapshot an unfinished SELECT would otherwise hold.
///
/// Column reads check the stored type: a value of another type (only possible in a file edited
/// by hand or damaged) reads as zero and is reported by column_error().
class Query {
 public:
  explicit Query(const Statement& statement) : stmt_(statement.get()) {}
  ~Query() {
    sqlite3_reset(stmt_);
    sqlite3_clear_bindings(stmt_);
  }
  Query(const Query&) = delete;
  Query& operator=(const Query&) = delete;

  Query& bind_int(std::int64_t value) { return note(sqlite3_bind_int64(stmt_, ++bound_, value)); }
  Query& bind_real(double value) { return note(sqlite3_bind_double(stmt_, ++bound_, value)); }
  Query& bind_text(std::string_view value) {
    return note(sqlite3_bind_text64(stmt_, ++bound_, value.empty() ? "" : value.data(),
                                    value.size(), SQLITE_STATIC, SQLITE_UTF8));
  }
  Query& bind_blob(std::string_view value) {
    return note(sqlite3_bind_blob64(stmt_, ++bound_, value.empty() ? "" : value.data(),
                                    value.size(), SQLITE_STATIC));
  }

  /// SQLITE_ROW, SQLITE_DONE or an error code (including a failed bind).
  int step() { return bind_rc_ != SQLITE_OK ? bind_rc_ : sqlite3_step(stmt_); }

  bool is_null(int column) const { return sqlite3_column_type(stmt_, column) == SQLITE_NULL; }
  std::int64_t integer(int column) {
    if (sqlite3_column_type(stmt_, column) != SQLITE_INTEGER) return wrong_type(column, "integer");
    return sqlite3_column_int64(stmt_, column);
  }
  std::optional<std::int64_t> optional_integer(int column) {
    if (is_null(column)) return std::nullopt;
    return integer(column);
  }
  /// An integer or a finite real, as a double.
  double real(int column) {
    const int type = sqlite3_column_type(stmt_, column);
    if (type != SQLITE_FLOAT && type != SQLITE_INTEGER) return wrong_type(column, "number");
    const double value = sqlite3_column_double(stmt_, column);
    if (!std::isfinite(value)) return wrong_type(column, "finite number");
    return value;
  }
  std::string text(int column) {
    if (sqlite3_column_type(stmt_, column) != SQLITE_TEXT) {
      wrong_type(column, "text");
      return {};
    }
    const auto* p = reinterpret_cast<const char*>(sqlite3_column_text(stmt_, column));
    if (!p) return {};  // out of memory while converting
    return std::string(p, static_cast<std::size_t>(sqlite3_column_bytes(stmt_, column)));
  }
  /// Empty while every column read had the expected type; otherwise the first mismatch, e.g.
  /// "column created_ms holds text, expected integer".
  const std::string& column_error() const { return column_error_; }

 private:
  Query& note(int rc) {
    if (bind_rc_ == SQLITE_OK) bind_rc_ = rc;
    return *this;
  }
  int wrong_type(int column, const char* expected) {
    if (column_error_.empty()) {
      static constexpr const char* kTypeNames[] = {"?", "integer", "real", "text", "blob", "null"};
      const int type = sqlite3_column_type(stmt_, column);
      const char* name = sqlite3_column_name(stmt_, column);
      column_error_ = std::string("column ") + (name ? name : "?") + " holds " +
                      kTypeNames[type >= 1 && type <= 5 ? type : 0] + ", expected " + expected;
    }
    return 0;
  }

  sqlite3_stmt* stmt_;
  int bound_ = 0;
  int bind_rc_ = SQLITE_OK;
  std::string column_error_;
};

/// Runs SQL without parameters or results (PRAGMA settings, schema scripts, BEGIN/COMMIT).
inline int exec(sqlite3* db, const char* sql) {
  return sqlite3_exec(db, sql, nullptr, nullptr, nullptr);
}

/// The first column of the first row of `sql` as text (PRAGMA results); SQLITE_OK or an error,
/// SQLITE_DONE when there is no row.
inline int single_text(sqlite3* db, std::string_view sql, std::string& out) {
  Statement statement;
  if (const int rc = statement.prepare(db, sql); rc != SQLITE_OK) return rc;
  Query query(statement);
  const int rc = query.step();
  if (rc != SQLITE_ROW) return rc;
  const auto* p = sqlite3_column_text(statement.get(), 0);
  out = p ? reinterpret_cast<const char*>(p) : "";
  return SQLITE_OK;
}

/// The first column of the first row of `sql` as an integer; like single_text.
inline int single_integer(sqlite3* db, std::string_view sql, std::int64_t& out) {
  Statement statement;
  if (const int rc = statement.prepare(db, sql); rc != SQLITE_OK) return rc;
  Query query(statement);
  const int rc = query.step();
  if (rc != SQLITE_ROW) return rc;
  out = query.integer(0);
  return query.column_error().empty() ? SQLITE_OK : SQLITE_MISMATCH;
}

/// A write transaction: begin() takes the write lock at once (BEGIN IMMEDIATE, waiting up to the
/// busy timeout), so nothing fails half-way for a lock another writer holds. Rolled back on
/// destruction unless commit() succeeded.
class Transaction {
 public:
  explicit Transaction(sqlite3* db) : db_(db) {}
  ~Transaction() {
    // A failed statement may already have rolled the transaction back (disk full, I/O error).
    if (open_ && !sqlite3_get_autocommit(db_)) exec(db_, "ROLLBACK");
  }
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;

  int begin() {
    const int rc = exec(db_, "BEGIN IMMEDIATE");
    open_ = rc == SQLITE_OK;
    return rc;
  }
  int commit() {
    const int rc = exec(db_, "COMMIT");
    if (rc == SQLITE_OK) open_ = false;
    return rc;
  }

 private:
  sqlite3* db_;
  bool open_ = false;
};

}  // namespace ricochet::db::sqlite
