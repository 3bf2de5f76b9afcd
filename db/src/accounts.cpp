/// Account rules over a Store (accounts.h).

#include "ricochet/db/accounts.h"

#include "account_rules.h"
#include "login_limits.h"
#include "password.h"

namespace ricochet::db {

namespace {

DbError error(DbErrorCode code, std::string message) {
  return DbError{code, std::move(message)};
}

DbError banned(const Account& account) {
  return error(DbErrorCode::AccountBanned, "account '" + account.username + "' is banned");
}

/// A hash for unknown names to be checked against; the password behind it is thrown away.
std::string make_dummy_hash(PasswordCost cost) {
  DbResult<std::string> hash = hash_password(random_token(), cost);
  return hash.ok() ? std::move(hash).value() : std::string();
}

}  // namespace

Accounts::Accounts(Store& store, AccountsOptions options)
    : store_(store),
      options_(std::move(options)),
      refusals_(options_.on_refusal),
      dummy_hash_(make_dummy_hash(options_.cost)) {}

// --- register ---

DbStatus Accounts::check_registration(std::string_view username, std::string_view password,
                                      std::string_view address, UnixMillis now) {
  if (DbStatus s = check_username(username); !s.ok()) return refusals_(s);
  if (DbStatus s = check_password_length(password.size(), options_.min_password_length, "password");
      !s.ok())
    return refusals_(s);
  // A taken name costs no hash and no place in the address's limit (insert_account checks again).
  DbResult<std::optional<AccountCredentials>> taken =
      store_.find_account_by_key(username_key(username));
  if (!taken.ok()) return refusals_(DbStatus(taken.error()));
  if (taken.value())
    return refusals_(
        DbStatus(error(DbErrorCode::DuplicateUsername,
                       "username '" + printable(username) + "' is taken (ignoring case)")));
  return refusals_(admit_registration(store_, options_, address, now));
}

DbResult<std::string> Accounts::hash_new_password(std::string_view password) const {
  return hash_password(password, options_.cost);
}

DbResult<AccountId> Accounts::finish_registration(std::string_view username,
                                                  const DbResult<std::string>& hash,
                                                  UnixMillis now) {
  if (!hash.ok()) return refusals_(DbResult<AccountId>(hash.error()));
  DbResult<AccountId> id =
      refusals_(store_.insert_account(username, username_key(username), hash.value(), now));
  if (id.ok()) ++counters_.registrations;
  return id;
}

DbResult<AccountId> Accounts::register_account(std::string_view username, std::string_view password,
                                               std::string_view address, UnixMillis now) {
  if (DbStatus s = check_registration(username, password, address, now); !s.ok()) return s.error();
  return finish_registration(username, hash_new_password(password), now);
}

// --- login ---

DbResult<Accounts::LoginAttempt> Accounts::begin_login(std::string_view username,
                                                       std::size_t password_bytes,
                                                       std::string_view address, UnixMillis now) {
  using R = DbResult<LoginAttempt>;
  if (DbStatus s = check_password_length(password_bytes, 0, "password"); !s.ok())
    return refusals_(R(s.error()));
  auto admitted = admit_login(store_, options_, username, address, now);
  if (!admitted.ok()) return refusals_(R(admitted.error()));
  LoginAttempt attempt;
  attempt.username = std::string(username);
  attempt.address = std::string(address);
  attempt.noted_failures = std::move(admitted).value();
  if (check_username(username).ok()) {
    DbResult<std::optional<AccountCredentials>> lookup =
        store_.find_account_by_key(username_key(username));
    if (!lookup.ok()) return refusals_(R(lookup.error()));
    attempt.found = std::move(lookup).value();
  }
  // Unknown names are checked against a dummy hash: the same work, so the same time.
  attempt.hash = attempt.found ? attempt.found->password_hash : dummy_hash_;
  return attempt;
}

Accounts::PasswordCheck Accounts::check_password(const LoginAttempt& attempt,
                                                 std::string_view password) const {
  PasswordCheck check;
  check.matches = password_matches(attempt.hash, password);
  if (check.matches && attempt.found && needs_rehash(attempt.hash, options_.cost)) {
    // Without the memory for the upgrade the login still succeeds, with the old hash.
    if (DbResult<std::string> upgraded = hash_new_password(password); upgraded.ok())
      check.upgraded_hash = std::move(upgraded).value();
  }
  return check;
}

DbResult<LoginResult> Accounts::finish_login(const LoginAttempt& attempt,
                                             const PasswordCheck& check, UnixMillis now) {
  using R = DbResult<LoginResult>;
  if (!attempt.found || !check.matches)  // begin_login already noted the failure
    return refusals_(R(error(DbErrorCode::WrongCredentials, "wrong username or password")));
  const Account& account = attempt.found->account;
  if (account.banned) return refusals_(R(banned(account)));
  LoginResult result;
  result.token = random_token();
  result.account = account.id;
  result.expires_ms = now + options_.session_lifetime_ms;
  R written = refusals_(atomically(store_, [&]() -> R {
    if (DbStatus s =
            forgive_login(store_, attempt.username, attempt.address, attempt.noted_failures);
        !s.ok())
      return s.error();
    if (!check.upgraded_hash.empty()) {
      if (DbStatus s = store_.set_password_hash(account.id, check.upgraded_hash); !s.ok())
        return s.error();
    }
    if (DbStatus s =
            store_.insert_session(token_hash(result.token), account.id, now, result.expires_ms);
        !s.ok())
      return s.error();
    if (DbStatus s = store_.set_last_login(account.id, now); !s.ok()) return s.error();
    if (DbResult<std::int64_t> pruned = store_.delete_expired_sessions(now); !pruned.ok())
      return pruned.error();
    return result;
  }));
  if (written.ok()) ++counters_.logins;
  return written;
}

DbResult<LoginResult> Accounts::login(std::string_view username, std::string_view password,
                                      std::string_view address, UnixMillis now) {
  DbResult<LoginAttempt> attempt = begin_login(username, password.size(), address, now);
  if (!attempt.ok()) return attempt.error();
  return finish_login(attempt.value(), check_password(attempt.value(), password), now);
}

// --- sessions ---

DbResult<SessionInfo> Accounts::check_session(std::string_view token, UnixMillis now) {
  using R = DbResult<SessionInfo>;
  ++counters_.session_checks;
  const std::string hash = token_hash(token);
  if (hash.empty()) {
    return refusals_(
        R(error(DbErrorCode::UnknownSession,
                "session token must be " + std::to_string(2 * kTokenBytes) +
                    " lowercase hex digits, got " + std::to_string(token.size()) + " characters")));
  }
  DbResult<std::optional<SessionRow>> row = store_.find_session(hash);
  if (!row.ok()) return refusals_(R(row.error()));
  if (!row.value()) return refusals_(R(error(DbErrorCode::UnknownSession, "no such session")));
  const SessionRow session = *row.value();
  if (session.expires_ms <= now) {
    (void)store_.delete_session(hash);
    return refusals_(R(error(DbErrorCode::ExpiredSession, "session expired")));
  }
  DbResult<Account> account = store_.account(session.account);
  if (!account.ok()) return refusals_(R(account.error()));
  if (account.value().banned) return refusals_(R(banned(account.value())));
  return SessionInfo{session.account, account.value().username, session.expires_ms};
}

DbStatus Accounts::revoke_session(std::string_view token) {
  const std::string hash = token_hash(token);
  if (hash.empty())
    return refusals_(DbStatus(error(DbErrorCode::UnknownSession, "malformed session token")));
  DbResult<std::optional<SessionRow>> row = store_.find_session(hash);
  if (!row.ok()) return refusals_(DbStatus(row.error()));
  if (!row.value())
    return refusals_(DbStatus(error(DbErrorCode::UnknownSession, "no such session")));
  return refusals_(store_.delete_session(hash));
}

// --- password change and bans ---

DbResult<Accounts::PasswordChange> Accounts::begin_password_change(AccountId id,
                                                                   std::string_view new_password) {
  using R = DbResult<PasswordChange>;
  if (DbStatus s =
          check_password_length(new_password.size(), options_.min_password_length, "new password");
      !s.ok())
    return refusals_(R(s.error()));
  DbResult<Account> account = store_.account(id);
  if (!account.ok()) return refusals_(R(account.error()));
  DbResult<std::optional<AccountCredentials>> found =
      store_.find_account_by_key(username_key(account.value().username));
  if (!found.ok()) return refusals_(R(found.error()));
  if (!found.value())
    return refusals_(
        R(error(DbErrorCode::UnknownAccount, "no account with id " + std::to_string(id))));
  return PasswordChange{id, found.value()->password_hash};
}

DbResult<std::string> Accounts::hash_password_change(const PasswordChange& change,
                                                     std::string_view old_password,
                                                     std::string_view new_password) const {
  if (old_password.size() > kMaxPasswordBytes || !password_matches(change.old_hash, old_password))
    return error(DbErrorCode::WrongCredentials, "wrong password");
  return hash_new_password(new_password);
}

DbStatus Accounts::finish_password_change(const PasswordChange& change,
                                          const DbResult<std::string>& new_hash) {
  if (!new_hash.ok()) return refusals_(DbStatus(new_hash.error()));
  // A new password with the old sessions still alive must never be left behind.
  return refusals_(atomically(store_, [&]() -> DbStatus {
    DbResult<Account> account = store_.account(change.account);
    if (!account.ok()) return account.error();
    DbResult<std::optional<AccountCredentials>> now =
        store_.find_account_by_key(username_key(account.value().username));
    if (!now.ok()) return now.error();
    if (!now.value() || now.value()->password_hash != change.old_hash)
      return error(DbErrorCode::WrongCredentials,
                   "the password was changed while this change was checked; try again");
    if (DbStatus s = store_.set_password_hash(change.account, new_hash.value()); !s.ok()) return s;
    return store_.delete_sessions_of(change.account);
  }));
}

DbStatus Accounts::change_password(AccountId id, std::string_view old_password,
                                   std::string_view new_password) {
  DbResult<PasswordChange> change = begin_password_change(id, new_password);
  if (!change.ok()) return change.error();
  return finish_password_change(change.value(),
                                hash_password_change(change.value(), old_password, new_password));
}

DbStatus Accounts::set_banned(AccountId id, bool banned) {
  // A ban with the account's sessions still alive must never be left behind.
  return refusals_(atomically(store_, [&]() -> DbStatus {
    if (DbStatus s = store_.set_banned(id, banned); !s.ok() || !banned) return s;
    return store_.delete_sessions_of(id);
  }));
}

DbResult<Account> Accounts::set_banned_by_name(std::string_view username, bool banned) {
  using R = DbResult<Account>;
  DbResult<std::optional<AccountCredentials>> found =
      store_.find_account_by_key(username_key(username));
  if (!found.ok()) return refusals_(R(found.error()));
  if (!found.value())
    return refusals_(
        R(error(DbErrorCode::UnknownAccount, "no account is named '" + printable(username) + "'")));
  Account account = found.value()->account;
  if (DbStatus s = set_banned(account.id, banned); !s.ok()) return s.error();
  account.banned = banned;
  return account;
}

}  // namespace ricochet::db
