#pragma once
/// Thin RAII over libpq: an owned connection, an owned result with checked column reads, the
/// parameters of one statement (text, or binary for bytea), a write transaction that rolls back
/// unless committed, and the mapping of SQLSTATE codes to DbErrorCode.
///
/// Header-only so that the db tests can open raw connections with the same helpers.

#include <libpq-fe.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ricochet/db/result.h"

namespace ricochet::db::postgres {

/// The key of the advisory lock every write transaction takes (Store::transaction): one lock per
/// database, shared by every server process on it. "RICOCHET" in ASCII.
inline constexpr std::int64_t kWriteLockKey = 0x5249434F43484554;

struct ConnectionCloser {
  void operator()(PGconn* conn) const { PQfinish(conn); }
};
/// An open (or failed, for its error message) connection.
using Connection = std::unique_ptr<PGconn, ConnectionCloser>;

/// Connects to a libpq connection string or postgresql:// URL; `connect_timeout_s` unless the
/// URL names its own. Notices ("relation already exists, skipping") are not printed.
inline Connection connect(const std::string& url, int connect_timeout_s) {
  const std::string timeout = std::to_string(connect_timeout_s);
  // Later entries win: the URL (expanded from dbname) may override the timeout.
  const char* keys[] = {"connect_timeout", "application_name", "dbname", nullptr};
  const char* values[] = {timeout.c_str(), "ricochet", url.c_str(), nullptr};
  Connection conn(PQconnectdbParams(keys, values, 1));
  if (conn)
    PQsetNoticeProcessor(
        conn.get(), [](void*, const char*) {}, nullptr);
  return conn;
}

/// "postgresql://user@host:port/dbname" of a connection string, without its password: what
/// error messages name.
inline std::string describe_url(const std::string& url) {
  char* error = nullptr;
  PQconninfoOption* options = PQconninfoParse(url.c_str(), &error);
  if (!options) {
    PQfreemem(error);
    return "postgresql (an unreadable URL)";
  }
  std::string user, host, port, dbname;
  for (PQconninfoOption* o = options; o->keyword; ++o) {
    if (!o->val) continue;
    const std::string_view key = o->keyword;
    if (key == "user") user = o->val;
    if (key == "host") host = o->val;
    if (key == "port") port = o->val;
    if (key == "dbname") dbname = o->val;
  }
  PQconninfoFree(options);
  return "postgresql://" + (user.empty() ? "" : user + "@") + host +
         (port.empty() ? "" : ":" + port) + "/" + dbname;
}

/// The DbErrorCode of an SQLSTATE (five characters; empty when libpq made the error itself,
/// which is a lost connection).
inline DbErrorCode error_code_of(std::string_view sqlstate) {
  if (sqlstate.empty()) return DbErrorCode::Unavailable;
  if (sqlstate.substr(0, 2) == "08") return DbErrorCode::Unavailable;     // connection exception
  if (sqlstate == "57P01" || sqlstate == "57P02" || sqlstate == "57P03")  // shutting down
    return DbErrorCode::Unavailable;
  if (sqlstate == "55P03" || sqlstate == "40001" || sqlstate == "40P01")  // lock timeout
    return DbErrorCode::Busy;
  if (sqlstate == "53200") return DbErrorCode::OutOfMemory;
  if (sqlstate == "XX001" || sqlstate == "XX002") return DbErrorCode::CorruptDatabase;
  return DbErrorCode::Storage;
}

/// A result, cleared on destruction. Column reads parse PostgreSQL's text format; a value that
/// does not parse reads as zero and is reported by column_error().
class Result {
 public:
  Result() = default;
  explicit Result(PGresult* result) : result_(result) {}
  ~Result() { PQclear(result_); }
  Result(Result&& other) noexcept : result_(other.result_) { other.result_ = nullptr; }
  Result& operator=(Result&& other) noexcept {
    std::swap(result_, other.result_);
    return *this;
  }
  Result(const Result&) = delete;
  Result& operator=(const Result&) = delete;

  PGresult* get() const { return result_; }
  /// PGRES_COMMAND_OK or PGRES_TUPLES_OK.
  bool ok() const {
    const ExecStatusType s = PQresultStatus(result_);
    return result_ && (s == PGRES_COMMAND_OK || s == PGRES_TUPLES_OK);
  }
  std::string sqlstate() const {
    const char* state = result_ ? PQresultErrorField(result_, PG_DIAG_SQLSTATE) : nullptr;
    return state ? state : "";
  }
  int rows() const { return PQntuples(result_); }
  /// Rows changed by an INSERT, UPDATE or DELETE.
  std::int64_t changed() const {
    std::int64_t n = 0;
    const char* text = PQcmdTuples(result_);
    std::from_chars(text, text + std::strlen(text), n);
    return n;
  }

  bool is_null(int row, int column) const { return PQgetisnull(result_, row, column) == 1; }
  std::int64_t integer(int row, int column) {
    std::int64_t value = 0;
    const std::string_view text = raw(row, column);
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || end != text.data() + text.size())
      return wrong(column, text, "integer");
    return value;
  }
  std::optional<std::int64_t> optional_integer(int row, int column) {
    if (is_null(row, column)) return std::nullopt;
    return integer(row, column);
  }
  /// A finite number.
  double real(int row, int column) {
    double value = 0;
    const std::string_view text = raw(row, column);
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value))
      return wrong(column, text, "finite number");
    return value;
  }
  std::string text(int row, int column) { return std::string(raw(row, column)); }
  /// Empty while every column read parsed; otherwise the first failure.
  const std::string& column_error() const { return column_error_; }

 private:
  std::string_view raw(int row, int column) {
    if (is_null(row, column)) {
      wrong(column, "NULL", "a value");
      return {};
    }
    return {PQgetvalue(result_, row, column),
            static_cast<std::size_t>(PQgetlength(result_, row, column))};
  }
  /// Notes the first column that did not read as expected: "column rating holds 'abc',
  /// expected finite number".
  int wrong(int column, std::string_view value, const char* expected) {
    if (column_error_.empty()) {
      const char* name = PQfname(result_, column);
      column_error_ = std::string("column ") + (name ? name : "?") + " holds '" +
                      std::string(value.substr(0, 40)) + "', expected " + expected;
    }
    return 0;
  }

  PGresult* result_ = nullptr;
  std::string column_error_;
};

/// The parameters of one statement ($1, $2, … in order). Numbers and text go as text (doubles
/// in the shortest form that reads back to the same value); bytes as binary (bytea).
class Params {
 public:
  Params& integer(std::int64_t value) { return add(std::to_string(value), 0); }
  Params& real(double value) {
    char buffer[32];
    const auto end = std::to_chars(buffer, buffer + sizeof buffer, value).ptr;
    return add(std::string(buffer, end), 0);
  }
  /// Text cannot hold a NUL byte in PostgreSQL: such a value makes the statement fail.
  Params& text(std::string_view value) {
    if (value.find('\0') != std::string_view::npos) bad_ = "a text value with a NUL byte";
    return add(std::string(value), 0);
  }
  Params& bytes(std::string_view value) { return add(std::string(value), 1); }

  /// Empty, or why the statement must not run.
  const std::string& problem() const { return bad_; }
  int size() const { return static_cast<int>(values_.size()); }

  /// Runs the prepared statement `name` with these parameters; results in text format.
  PGresult* exec(PGconn* conn, const char* name) const {
    std::vector<const char*> values;
    std::vector<int> lengths;
    for (const std::string& v : values_) {
      values.push_back(v.c_str());
      lengths.push_back(static_cast<int>(v.size()));
    }
    return PQexecPrepared(conn, name, size(), values.data(), lengths.data(), formats_.data(), 0);
  }

 private:
  Params& add(std::string value, int format) {
    values_.push_back(std::move(value));
    formats_.push_back(format);
    return *this;
  }
  std::vector<std::string> values_;
  std::vector<int> formats_;
  std::string bad_;
};

/// Runs SQL without parameters (SET, BEGIN/COMMIT, schema scripts of several statements).
inline Result exec(PGconn* conn, const char* sql) {
  return Result(PQexec(conn, sql));
}

/// "<where>: <what> failed: <PostgreSQL's message>", with the code of its SQLSTATE. A result
/// without an error message (a COMMIT that rolled back) takes the connection's.
inline DbError error_from(PGconn* conn, const Result& result, std::string_view where,
                          std::string_view what) {
  const char* message = result.get() ? PQresultErrorMessage(result.get()) : "";
  if (!message || !*message) message = PQerrorMessage(conn);
  if (!message || !*message) message = "the transaction was rolled back";
  std::string text = std::string(where) + ": " + std::string(what) + " failed: " + message;
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  DbErrorCode code = error_code_of(result.sqlstate());
  // A statement that failed on a healthy connection without an SQLSTATE is no lost connection.
  if (code == DbErrorCode::Unavailable && PQstatus(conn) == CONNECTION_OK && result.get() &&
      PQresultStatus(result.get()) != PGRES_FATAL_ERROR)
    code = DbErrorCode::Storage;
  if (code == DbErrorCode::Unavailable) text += "; the database server is unreachable, retry later";
  if (code == DbErrorCode::Busy)
    text += "; another server held the write lock too long, retry later";
  return DbError{code, std::move(text)};
}

/// A write transaction: begin() takes the database's write lock (kWriteLockKey), waiting up to
/// the connection's lock_timeout, so nothing fails half-way for another writer and what it reads
/// cannot change under it. Rolled back on destruction unless commit() succeeded.
class Transaction {
 public:
  explicit Transaction(PGconn* conn) : conn_(conn) {}
  ~Transaction() {
    if (open_ && PQtransactionStatus(conn_) != PQTRANS_IDLE) exec(conn_, "ROLLBACK");
  }
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;

  /// An empty (null) result on success, otherwise the one that failed.
  Result begin() {
    // READ COMMITTED, not REPEATABLE READ: each statement's snapshot is taken after the lock is
    // had, so it sees every commit of the writer before; a transaction-wide snapshot would be
    // taken by the lock statement itself, before the wait, and miss them (a lost update).
    Result r = exec(conn_, "BEGIN ISOLATION LEVEL READ COMMITTED");
    if (!r.ok()) return r;
    open_ = true;
    r = exec(conn_,
             ("SELECT pg_advisory_xact_lock(" + std::to_string(kWriteLockKey) + ")").c_str());
    if (!r.ok()) return r;
    return Result();
  }
  /// Like begin(). COMMIT of a transaction that failed inside answers ROLLBACK: a failure too.
  Result commit() {
    Result r = exec(conn_, "COMMIT");
    if (r.ok() && std::string_view(PQcmdStatus(r.get())) != "COMMIT") return r;
    if (r.ok()) {
      open_ = false;
      return Result();
    }
    return r;
  }

 private:
  PGconn* conn_;
  bool open_ = false;
};

}  // namespace ricochet::db::postgres
