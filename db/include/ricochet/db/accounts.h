#pragma once
/// Account rules over any Store: usernames, Argon2id passwords, session tokens, rate limits.
///
///   register  name 3–24 of [A-Za-z0-9_.-], unique ignoring case (a taken name is refused
///             before any hashing); password 8..1024 bytes, stored as crypto_pwhash_str
///             (Argon2id, interactive limits by default); registrations counted per address in
///             the store (RateLimited past the limit, shared by every server process)
///   login     checks the password (against a dummy hash when the name is unknown, so the time
///             taken does not tell whether an account exists), refuses banned accounts, counts
///             failures per (account, address), per account and per address in the store
///             (RateLimited past a limit, shared by every server process on the database), and
///             returns a random 256-bit token; the store keeps only its SHA-256, with an expiry
///   session   check, revoke (logout); expired sessions are deleted as logins go on (only a
///             login adds one, so the table holds at most one lifetime's logins); banning an
///             account or changing its password revokes all its sessions in the same transaction
///
/// Register, login and change_password each run in three steps, so that a caller can run the
/// Argon2id work (~100 ms) on another thread: begin (DB) → hash or check (any thread, touches
/// no state) → finish (DB). The one-call forms run the three in a row.
///
/// Time is a parameter (Unix ms) of every call, so expiry and rate limits are testable.

#include <cstddef>
#include <cstdint>
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

/// At most `max_events` events (failed logins, registrations) within `window_ms`; further
/// attempts are refused with RateLimited (without any hashing) until the oldest event leaves
/// the window.
struct RateLimit {
  int max_events = 5;
  UnixMillis window_ms = 60'000;
};

/// The login limits follow OWASP's authentication guidance: whoever guesses is stopped, the
/// owner signing in from elsewhere is not. `address` below is what the caller names a client by
/// (the server passes an IPv4 address or an IPv6 /64).
struct AccountsOptions {
  PasswordCost cost = PasswordCost::Interactive;
  std::size_t min_password_length = 8;  ///< bytes
  UnixMillis session_lifetime_ms = 24 * 3600 * 1000LL;
  /// Failed logins of one account from one address, every step checked: 5 a minute, then 20
  /// an hour, so a guesser that keeps going gets fewer tries per minute (a back-off).
  std::vector<RateLimit> per_account_address{{5, 60'000}, {20, 3'600'000}};
  /// Failed logins of one account from all addresses together: looser, so that it takes many
  /// addresses to reach, and then the account is refused everywhere until the window passes.
  RateLimit per_account{100, 900'000};
  /// Failed logins from one address, whatever the accounts (one address guessing many).
  RateLimit per_address{20, 60'000};
  /// Accounts registered from one address (each costs a hash and a row).
  RateLimit registrations_per_address{10, 3'600'000};
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
  std::uint64_t session_checks = 0;
};

class Accounts {
 public:
  /// The store must outlive this object.
  Accounts(Store& store, AccountsOptions options = {});

  /// `address` names the client for the per-address limits; empty skips them.
  DbResult<AccountId> register_account(std::string_view username, std::string_view password,
                                       std::string_view address, UnixMillis now);
  DbResult<LoginResult> login(std::string_view username, std::string_view password,
                              std::string_view address, UnixMillis now);
  DbResult<SessionInfo> check_session(std::string_view token, UnixMillis now);
  /// Logout: the token stops working at once (UnknownSession when it is not a live session).
  DbStatus revoke_session(std::string_view token);
  /// Checks the old password first (WrongCredentials); revokes every session of the account.
  DbStatus change_password(AccountId id, std::string_view old_password,
                           std::string_view new_password);
  /// Banning revokes every session of the account; unbanning lets it log in again.
  DbStatus set_banned(AccountId id, bool banned);
  /// set_banned of the account named `username` (ignoring case); the account as it is now, or
  /// UnknownAccount when no account has that name.
  DbResult<Account> set_banned_by_name(std::string_view username, bool banned);

  // --- register: check (DB) → hash_new_password (any thread) → finish_registration (DB) ---
  /// The name and password rules, the name not taken, and the address's registration limit
  /// (noting this registration).
  DbStatus check_registration(std::string_view username, std::string_view password,
                              std::string_view address, UnixMillis now);
  /// Argon2id at the configured cost; OutOfMemory when libsodium could not allocate it.
  DbResult<std::string> hash_new_password(std::string_view password) const;
  DbResult<AccountId> finish_registration(std::string_view username,
                                          const DbResult<std::string>& hash, UnixMillis now);

  // --- login: begin_login (DB) → check_password (any thread) → finish_login (DB) ---
  struct LoginAttempt {
    std::string username;                     ///< as given
    std::optional<AccountCredentials> found;  ///< nullopt: unknown (or invalid) name
    std::string address;                      ///< as given
    std::string hash;  ///< what the password is checked against: the account's, or a dummy
    std::vector<std::int64_t> noted_failures;  ///< noted by begin_login, forgiven on success
  };
  struct PasswordCheck {
    bool matches = false;
    std::string upgraded_hash;  ///< the password at the configured cost, when the stored hash
                                ///< was made with other limits; empty otherwise
  };
  /// Rate limits (noting the attempt as failed until it succeeds) and the account lookup.
  DbResult<LoginAttempt> begin_login(std::string_view username, std::size_t password_bytes,
                                     std::string_view address, UnixMillis now);
  PasswordCheck check_password(const LoginAttempt& attempt, std::string_view password) const;
  /// Refuses banned accounts; writes the upgraded hash, the session and the login time at once,
  /// and deletes the sessions that expired before `now`.
  DbResult<LoginResult> finish_login(const LoginAttempt& attempt, const PasswordCheck& check,
                                     UnixMillis now);

  // --- password change: begin (DB) → hash_password_change (any thread) → finish (DB) ---
  struct PasswordChange {
    AccountId account = 0;
    std::string old_hash;  ///< the stored hash the old password is checked against
  };
  /// The new password's rules and the account lookup.
  DbResult<PasswordChange> begin_password_change(AccountId id, std::string_view new_password);
  /// The new password's hash, or WrongCredentials when the old one does not match.
  DbResult<std::string> hash_password_change(const PasswordChange& change,
                                             std::string_view old_password,
                                             std::string_view new_password) const;
  /// Writes the new hash and revokes every session at once; WrongCredentials when the password
  /// was changed by someone else since begin_password_change.
  DbStatus finish_password_change(const PasswordChange& change,
                                  const DbResult<std::string>& new_hash);

  const AccountsCounters& counters() const { return counters_; }
  const Refusals& refusals() const { return refusals_; }

 private:
  Store& store_;
  AccountsOptions options_;
  AccountsCounters counters_;
  Refusals refusals_;
  std::string dummy_hash_;  ///< verified against when the username is unknown
};

}  // namespace ricochet::db
