#pragma once
/// Account rules over any Store: usernames, Argon2id passwords, session tokens, rate limits.
///
///   register  name 3–24 of [A-Za-z0-9_.-], unique ignoring case; password 8..1024 bytes,
///             stored as crypto_pwhash_str (Argon2id, interactive limits by default)
///   login     checks the password (against a dummy hash when the name is unknown, so the time
///             taken does not tell whether an account exists), refuses banned accounts, counts
///             failures per account and per address (RateLimited past the limit), and returns a
///             random 256-bit token; the store keeps only its SHA-256, with an expiry
///   session   check, revoke; banning an account revokes all its sessions
///
/// Time is a parameter (Unix ms) of every call, so expiry and rate limits are testable.

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ricochet/db/records.h"
#include "ricochet/db/refusals.h"
#include "ricochet/db/result.h"
#include "ricochet/db/store.h"

namespace ricochet::db {

inline constexpr std::size_t kMaxPasswordBytes = 1024;
inline constexpr std::size_t kTokenBytes = 32;  ///< 256 bits; the text form is 64 hex digits

/// Argon2id work per hash. Interactive is libsodium's recommendation for logins (64 MiB, 2
/// passes); Minimum exists for tests and for seeding benches, never for production.
enum class PasswordCost { Interactive, Moderate, Minimum };

/// At most `max_failures` failed logins within `window_ms`; further attempts are refused with
/// RateLimited (without checking the password) until the oldest failure leaves the window.
struct RateLimit {
  int max_failures = 5;
  UnixMillis window_ms = 60'000;
};

struct AccountsOptions {
  PasswordCost cost = PasswordCost::Interactive;
  std::size_t min_password_length = 8;  ///< bytes
  UnixMillis session_lifetime_ms = 24 * 3600 * 1000LL;
  RateLimit per_account{5, 60'000};
  RateLimit per_address{20, 60'000};
  OnRefusal on_refusal;  ///< see refusals.h
};

struct LoginResult {
  std::string token;  ///< 64 lowercase hex digits; shown once, never stored
  AccountId account = 0;
  UnixMillis expires_ms = 0;
};

struct SessionInfo {
  AccountId account = 0;
  std::string username;
  UnixMillis expires_ms = 0;
};

/// What succeeded, for metrics (what was refused is in Accounts::refusals()).
struct AccountsCounters {
  std::uint64_t registrations = 0;
  std::uint64_t logins = 0;
  std::uint64_t password_checks = 0;  ///< Argon2id verifications, real or dummy
  std::uint64_t session_checks = 0;
};

class Accounts {
 public:
  /// The store must outlive this object.
  Accounts(Store& store, AccountsOptions options = {});

  DbResult<AccountId> register_account(std::string_view username, std::string_view password,
                                       UnixMillis now);
  /// `address` names the client (an IP) for the per-address limit; empty skips that limit.
  DbResult<LoginResult> login(std::string_view username, std::string_view password,
                              std::string_view address, UnixMillis now);
  DbResult<SessionInfo> check_session(std::string_view token, UnixMillis now);

  // --- register and login in steps, for a caller that runs Argon2id on another thread ---
  // (DbWorker does: the DB thread then never spends ~100 ms per login hashing.)

  /// The name and password rules of register_account, without hashing or storing.
  DbStatus check_registration(std::string_view username, std::string_view password);
  /// Argon2id at the configured cost. Reads only immutable options: any thread may call it.
  /// Empty when libsodium could not allocate the memory.
  std::string hash_new_password(std::string_view password) const;
  DbResult<AccountId> finish_registration(std::string_view username, const std::string& hash,
                                          UnixMillis now);

  /// A login between its lookup and its password check.
  struct LoginAttempt {
    std::string username;  ///< as given
    std::string address;
    std::optional<AccountCredentials> found;  ///< nullopt: unknown (or invalid) name
    std::string hash;  ///< what the password is checked against: the account's, or a dummy
    UnixMillis started_ms = 0;
  };
  /// Rate limits and the account lookup; no hashing.
  DbResult<LoginAttempt> begin_login(std::string_view username, std::size_t password_bytes,
                                     std::string_view address, UnixMillis now);
  /// The Argon2id check. Touches no state: any thread may call it.
  static bool password_verifies(const LoginAttempt& attempt, std::string_view password);
  /// Counts the check, records failures, refuses banned accounts, issues the session.
  DbResult<LoginResult> finish_login(const LoginAttempt& attempt, bool password_ok,
                                     std::string_view password, UnixMillis now);
  DbStatus revoke_session(std::string_view token);
  /// Checks the old password first (WrongCredentials); revokes every session of the account.
  DbStatus change_password(AccountId id, std::string_view old_password,
                           std::string_view new_password);
  /// Banning revokes every session of the account; unbanning lets it log in again.
  DbStatus set_banned(AccountId id, bool banned);

  const AccountsCounters& counters() const { return counters_; }
  const Refusals& refusals() const { return refusals_; }

  /// Empty when the name is acceptable; otherwise what is wrong with it.
  static std::string check_username(std::string_view username);

 private:
  template <class T>
  T counted(T result) {
    return refusals_(std::move(result));
  }
  DbStatus counted_status(DbStatus status) { return refusals_(std::move(status)); }
  bool over_limit(const std::string& key, const RateLimit& limit, UnixMillis now);
  void note_failure(const std::string& key, UnixMillis now);
  /// Drops the failure noted at `when` (or, with `all`, every failure) under `key`.
  void forget_failure(const std::string& key, UnixMillis when, bool all);
  bool verify_password(const std::string& hash, std::string_view password);

  Store& store_;
  AccountsOptions options_;
  AccountsCounters counters_;
  Refusals refusals_;
  std::string dummy_hash_;  ///< verified against when the username is unknown
  /// Failure times per "account:<key>" and "address:<ip>", oldest first, pruned as they age.
  std::map<std::string, std::vector<UnixMillis>> failures_;
};

}  // namespace ricochet::db
