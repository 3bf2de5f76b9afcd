/// Account rules over a Store (accounts.h).

#include "ricochet/db/accounts.h"

#include <algorithm>

#include "password.h"

namespace ricochet::db {

namespace {

constexpr std::size_t kMinUsername = 3;
constexpr std::size_t kMaxUsername = 24;
/// Rate-limit keys kept before stale ones are swept (bounds memory under a spray of names).
constexpr std::size_t kMaxTrackedKeys = 100'000;

DbError error(DbErrorCode code, std::string message) {
  return DbError{code, std::move(message)};
}

std::string lowercase(std::string_view s) {
  std::string out(s);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) {
    return static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
  });
  return out;
}

/// The name as it may appear in a message: printable ASCII kept, the rest escaped, truncated.
std::string printable(std::string_view s) {
  std::string out;
  for (const char c : s.substr(0, 40)) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u < 0x7f) {
      out += c;
    } else {
      static const char* digits = "0123456789abcdef";
      out += "\\x";
      out += digits[u >> 4];
      out += digits[u & 15];
    }
  }
  if (s.size() > 40) out += "...";
  return out;
}

}  // namespace

Accounts::Accounts(Store& store, AccountsOptions options)
    : store_(store),
      options_(options),
      refusals_(options_.on_refusal),
      dummy_hash_(hash_password(random_token(), options.cost)) {}

std::string Accounts::check_username(std::string_view username) {
  if (username.size() < kMinUsername || username.size() > kMaxUsername) {
    return "username must be 3-24 characters, got " + std::to_string(username.size()) + " ('" +
           printable(username) + "')";
  }
  for (const char c : username) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '-' || c == '.';
    if (!ok) {
      return "username may hold only letters, digits, '_', '-' and '.', got '" +
             printable(username) + "'";
    }
  }
  return {};
}

bool Accounts::verify_password(const std::string& hash, std::string_view password) {
  ++counters_.password_checks;
  return password_matches(hash, password);
}

bool Accounts::over_limit(const std::string& key, const RateLimit& limit, UnixMillis now) {
  const auto it = failures_.find(key);
  if (it == failures_.end()) return false;
  std::vector<UnixMillis>& times = it->second;
  std::erase_if(times, [&](UnixMillis t) { return t <= now - limit.window_ms; });
  if (times.empty()) {
    failures_.erase(it);
    return false;
  }
  return static_cast<int>(times.size()) >= limit.max_failures;
}

void Accounts::note_failure(const std::string& key, UnixMillis now) {
  if (failures_.size() >= kMaxTrackedKeys) {
    const UnixMillis window =
        std::max(options_.per_account.window_ms, options_.per_address.window_ms);
    std::erase_if(failures_,
                  [&](const auto& entry) { return entry.second.back() <= now - window; });
  }
  failures_[key].push_back(now);
}

DbStatus Accounts::check_registration(std::string_view username, std::string_view password) {
  if (const std::string why = check_username(username); !why.empty())
    return counted_status(error(DbErrorCode::InvalidUsername, why));
  if (password.empty())
    return counted_status(error(DbErrorCode::EmptyPassword, "password must not be empty"));
  if (password.size() < options_.min_password_length) {
    return counted_status(
        error(DbErrorCode::PasswordTooShort, "password must be at least " +
                                                 std::to_string(options_.min_password_length) +
                                                 " bytes, got " + std::to_string(password.size())));
  }
  if (password.size() > kMaxPasswordBytes) {
    return counted_status(error(DbErrorCode::PasswordTooLong,
                                "password must be at most " + std::to_string(kMaxPasswordBytes) +
                                    " bytes, got " + std::to_string(password.size())));
  }
  return {};
}

std::string Accounts::hash_new_password(std::string_view password) const {
  return hash_password(password, options_.cost);
}

DbResult<AccountId> Accounts::finish_registration(std::string_view username,
                                                  const std::string& hash, UnixMillis now) {
  if (hash.empty()) {
    return counted(
        DbResult<AccountId>(error(DbErrorCode::OutOfMemory, "password hashing ran out of memory")));
  }
  DbResult<AccountId> id = counted(store_.insert_account(username, lowercase(username), hash, now));
  if (id.ok()) ++counters_.registrations;
  return id;
}

void Accounts::forget_failure(const std::string& key, UnixMillis when, bool all) {
  const auto it = failures_.find(key);
  if (it == failures_.end()) return;
  std::vector<UnixMillis>& times = it->second;
  if (all) {
    times.clear();
  } else if (const auto t = std::find(times.begin(), times.end(), when); t != times.end()) {
    times.erase(t);
  }
  if (times.empty()) failures_.erase(it);
}

DbResult<AccountId> Accounts::register_account(std::string_view username, std::string_view password,
                                               UnixMillis now) {
  if (DbStatus s = check_registration(username, password); !s.ok()) return s.error();
  return finish_registration(username, hash_new_password(password), now);
}

DbResult<Accounts::LoginAttempt> Accounts::begin_login(std::string_view username,
                                                       std::size_t password_bytes,
                                                       std::string_view address, UnixMillis now) {
  using R = DbResult<LoginAttempt>;
  const std::string key = lowercase(username);
  if (!address.empty() &&
      over_limit("address:" + std::string(address), options_.per_address, now)) {
    return counted(R(error(DbErrorCode::RateLimited,
                           "too many failed logins from " + printable(address) + "; retry later")));
  }
  if (over_limit("account:" + key, options_.per_account, now)) {
    return counted(R(error(DbErrorCode::RateLimited, "too many failed logins for '" +
                                                         printable(username) + "'; retry later")));
  }
  if (password_bytes > kMaxPasswordBytes) {
    return counted(R(error(DbErrorCode::PasswordTooLong,
                           "password must be at most " + std::to_string(kMaxPasswordBytes) +
                               " bytes, got " + std::to_string(password_bytes))));
  }
  // Counted as a failure until it succeeds, so attempts in flight at once (the password check
  // runs elsewhere under DbWorker) cannot slip past the limit together.
  note_failure("account:" + key, now);
  if (!address.empty()) note_failure("address:" + std::string(address), now);
  LoginAttempt attempt;
  attempt.username = std::string(username);
  attempt.address = std::string(address);
  attempt.started_ms = now;
  if (check_username(username).empty()) {
    DbResult<std::optional<AccountCredentials>> lookup = store_.find_account_by_key(key);
    if (!lookup.ok()) return counted(R(lookup.error()));
    attempt.found = std::move(lookup).value();
  }
  // Unknown names are checked against a dummy hash: the same work, so the same time.
  attempt.hash = attempt.found ? attempt.found->password_hash : dummy_hash_;
  return attempt;
}

bool Accounts::password_verifies(const LoginAttempt& attempt, std::string_view password) {
  return password_matches(attempt.hash, password);
}

DbResult<LoginResult> Accounts::finish_login(const LoginAttempt& attempt, bool password_ok,
                                             std::string_view password, UnixMillis now) {
  using R = DbResult<LoginResult>;
  ++counters_.password_checks;
  if (!attempt.found || !password_ok)  // begin_login already counted the failure
    return counted(R(error(DbErrorCode::WrongCredentials, "wrong username or password")));
  const Account& account = attempt.found->account;
  if (account.banned) {
    return counted(
        R(error(DbErrorCode::AccountBanned, "account '" + account.username + "' is banned")));
  }
  forget_failure("account:" + lowercase(attempt.username), attempt.started_ms, true);
  if (!attempt.address.empty())
    forget_failure("address:" + attempt.address, attempt.started_ms, false);
  LoginResult result;
  result.token = random_token();
  result.account = account.id;
  result.expires_ms = now + options_.session_lifetime_ms;
  // The upgraded hash, the session and the login time are written together or not at all.
  const DbStatus written = atomically(store_, [&]() -> DbStatus {
    if (needs_rehash(attempt.found->password_hash, options_.cost)) {
      const std::string rehashed = hash_new_password(password);
      if (!rehashed.empty()) {
        if (DbStatus s = store_.set_password_hash(account.id, rehashed); !s.ok()) return s;
      }
    }
    if (DbStatus s =
            store_.insert_session(token_hash(result.token), account.id, now, result.expires_ms);
        !s.ok())
      return s;
    return store_.set_last_login(account.id, now);
  });
  if (!written.ok()) return counted(R(written.error()));
  ++counters_.logins;
  return result;
}

DbResult<LoginResult> Accounts::login(std::string_view username, std::string_view password,
                                      std::string_view address, UnixMillis now) {
  DbResult<LoginAttempt> attempt = begin_login(username, password.size(), address, now);
  if (!attempt.ok()) return attempt.error();
  const bool ok = password_verifies(attempt.value(), password);
  return finish_login(attempt.value(), ok, password, now);
}

DbResult<SessionInfo> Accounts::check_session(std::string_view token, UnixMillis now) {
  using R = DbResult<SessionInfo>;
  ++counters_.session_checks;
  const std::string hash = token_hash(token);
  if (hash.empty()) {
    return counted(
        R(error(DbErrorCode::UnknownSession,
                "session token must be " + std::to_string(2 * kTokenBytes) +
                    " lowercase hex digits, got " + std::to_string(token.size()) + " characters")));
  }
  DbResult<std::optional<SessionRow>> row = store_.find_session(hash);
  if (!row.ok()) return counted(R(row.error()));
  if (!row.value()) return counted(R(error(DbErrorCode::UnknownSession, "no such session")));
  const SessionRow session = *row.value();
  if (session.expires_ms <= now) {
    (void)store_.delete_session(hash);
    return counted(R(error(DbErrorCode::ExpiredSession, "session expired")));
  }
  DbResult<Account> account = store_.account(session.account);
  if (!account.ok()) return counted(R(account.error()));
  if (account.value().banned) {
    return counted(R(
        error(DbErrorCode::AccountBanned, "account '" + account.value().username + "' is banned")));
  }
  return SessionInfo{session.account, account.value().username, session.expires_ms};
}

DbStatus Accounts::revoke_session(std::string_view token) {
  const std::string hash = token_hash(token);
  if (hash.empty())
    return counted_status(error(DbErrorCode::UnknownSession, "malformed session token"));
  DbResult<std::optional<SessionRow>> row = store_.find_session(hash);
  if (!row.ok()) return counted_status(row.error());
  if (!row.value()) return counted_status(error(DbErrorCode::UnknownSession, "no such session"));
  return counted_status(store_.delete_session(hash));
}

DbStatus Accounts::change_password(AccountId id, std::string_view old_password,
                                   std::string_view new_password) {
  DbResult<Account> account = store_.account(id);
  if (!account.ok()) return counted_status(account.error());
  DbResult<std::optional<AccountCredentials>> found =
      store_.find_account_by_key(lowercase(account.value().username));
  if (!found.ok()) return counted_status(found.error());
  if (!found.value() || old_password.size() > kMaxPasswordBytes ||
      !verify_password(found.value()->password_hash, old_password)) {
    return counted_status(error(DbErrorCode::WrongCredentials, "wrong password"));
  }
  if (new_password.empty())
    return counted_status(error(DbErrorCode::EmptyPassword, "new password must not be empty"));
  if (new_password.size() < options_.min_password_length) {
    return counted_status(error(DbErrorCode::PasswordTooShort,
                                "new password must be at least " +
                                    std::to_string(options_.min_password_length) + " bytes"));
  }
  if (new_password.size() > kMaxPasswordBytes) {
    return counted_status(
        error(DbErrorCode::PasswordTooLong,
              "new password must be at most " + std::to_string(kMaxPasswordBytes) + " bytes"));
  }
  const std::string hash = hash_new_password(new_password);
  if (hash.empty())
    return counted_status(error(DbErrorCode::OutOfMemory, "password hashing ran out of memory"));
  // A new password with the old sessions still alive must never be left behind.
  return counted_status(atomically(store_, [&]() -> DbStatus {
    if (DbStatus s = store_.set_password_hash(id, hash); !s.ok()) return s;
    return store_.delete_sessions_of(id);
  }));
}

DbStatus Accounts::set_banned(AccountId id, bool banned) {
  // A ban with the account's sessions still alive must never be left behind.
  return counted_status(atomically(store_, [&]() -> DbStatus {
    if (DbStatus s = store_.set_banned(id, banned); !s.ok() || !banned) return s;
    return store_.delete_sessions_of(id);
  }));
}

}  // namespace ricochet::db
