#pragma once
/// Errors of the persistence layer: one code per thing that can go wrong, each with a message
/// that says what was expected and what came.

#include <cstddef>
#include <string>
#include <utility>
#include <variant>

namespace ricochet::db {

enum class DbErrorCode {
  InvalidUsername,    ///< not 3–24 of letters, digits, '_', '-', '.'
  DuplicateUsername,  ///< taken, compared case-insensitively
  EmptyPassword,
  PasswordTooShort,  ///< fewer than AccountsOptions::min_password_length bytes
  PasswordTooLong,   ///< more than kMaxPasswordBytes (hashing cost is bounded)
  WrongCredentials,  ///< unknown username or wrong password: the same code, so names don't leak
  AccountBanned,
  UnknownAccount,  ///< no account with this id
  UnknownSession,  ///< never issued, revoked, or malformed token
  ExpiredSession,
  RateLimited,   ///< too many failed logins for this account or address; retry later
  InvalidMatch,  ///< a match record with missing or out-of-range fields
  // placement (placement.h)
  InvalidPlacement,   ///< a directory row, hosted match, request or ticket with bad fields
  NoServerAvailable,  ///< no live game server has a free seat for the mode and map; retry later
  UnknownModeOrMap,   ///< no live game server hosts that mode (and map)
  UnknownTicket,      ///< never issued, malformed, already claimed, or another server's/account's
  ExpiredTicket,
  SchemaTooNew,     ///< the file was written by a newer Ricochet; this binary refuses it
  CorruptDatabase,  ///< not a database, or integrity check failed
  CannotOpen,       ///< the file cannot be opened or created
  Busy,             ///< locked by another process for longer than the busy timeout
  Unavailable,      ///< the database server is down or the connection was lost; retry later
  QueueFull,        ///< the DB worker already holds DbWorkerOptions::max_queued jobs
  Storage,          ///< any other storage failure (disk full, I/O error, a constraint)
  OutOfMemory,      ///< the memory for a password hash (64 MiB for Argon2id) or SQLite ran out
  Stopped,          ///< the DB worker was stopped before the job ran
};

/// Stable lowercase name of a code, for logs and counters ("duplicate_username").
const char* to_string(DbErrorCode code);
inline constexpr std::size_t kDbErrorCodeCount = static_cast<std::size_t>(DbErrorCode::Stopped) + 1;

struct DbError {
  DbErrorCode code;
  std::string message;
};

/// A value or a DbError.
template <class T>
class [[nodiscard]] DbResult {
 public:
  DbResult(T value) : v_(std::move(value)) {}        // NOLINT: implicit by design
  DbResult(DbError error) : v_(std::move(error)) {}  // NOLINT
  bool ok() const { return v_.index() == 0; }
  explicit operator bool() const { return ok(); }
  const T& value() const& { return std::get<0>(v_); }
  T& value() & { return std::get<0>(v_); }
  T&& value() && { return std::get<0>(std::move(v_)); }
  const DbError& error() const { return std::get<1>(v_); }

 private:
  std::variant<T, DbError> v_;
};

/// Success or a DbError.
class [[nodiscard]] DbStatus {
 public:
  DbStatus() = default;
  DbStatus(DbError error) : error_(std::move(error)), ok_(false) {}  // NOLINT
  bool ok() const { return ok_; }
  explicit operator bool() const { return ok_; }
  const DbError& error() const { return error_; }

 private:
  DbError error_{DbErrorCode::Storage, {}};
  bool ok_ = true;
};

}  // namespace ricochet::db
