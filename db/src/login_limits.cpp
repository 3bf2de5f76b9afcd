/// Failed-login rate limits over the store (login_limits.h).

#include "login_limits.h"

#include <algorithm>
#include <string>

#include "account_rules.h"

namespace ricochet::db {

namespace {

std::string account_key(std::string_view username) {
  return "account:" + username_key(username);
}

std::string address_key(std::string_view address) {
  return "address:" + std::string(address);
}

/// RateLimited when `key` has `limit.max_failures` failures within the window ending at `now`.
DbStatus check_limit(Store& store, const std::string& key, const RateLimit& limit, UnixMillis now,
                     const std::string& whose) {
  const DbResult<std::int64_t> failures = store.count_login_failures(key, now - limit.window_ms);
  if (!failures.ok()) return failures.error();
  if (failures.value() < limit.max_failures) return {};
  return DbError{DbErrorCode::RateLimited,
                 std::to_string(failures.value()) + " failed logins " + whose + " in the last " +
                     std::to_string(limit.window_ms / 1000) + " s; retry later"};
}

}  // namespace

DbResult<std::optional<std::int64_t>> admit_login(Store& store, const AccountsOptions& options,
                                                  std::string_view username,
                                                  std::string_view address, UnixMillis now) {
  using R = DbResult<std::optional<std::int64_t>>;
  const UnixMillis longest = std::max(options.per_account.window_ms, options.per_address.window_ms);
  return atomically(store, [&]() -> R {
    if (DbStatus s = store.delete_login_failures_until(now - longest); !s.ok()) return s.error();
    if (!address.empty()) {
      if (DbStatus s = check_limit(store, address_key(address), options.per_address, now,
                                   "from " + printable(address));
          !s.ok())
        return s.error();
    }
    if (DbStatus s = check_limit(store, account_key(username), options.per_account, now,
                                 "for '" + printable(username) + "'");
        !s.ok())
      return s.error();
    if (auto noted = store.insert_login_failure(account_key(username), now); !noted.ok())
      return noted.error();
    if (address.empty()) return std::optional<std::int64_t>();
    DbResult<std::int64_t> noted = store.insert_login_failure(address_key(address), now);
    if (!noted.ok()) return noted.error();
    return std::optional<std::int64_t>(noted.value());
  });
}

DbStatus forgive_login(Store& store, std::string_view username,
                       std::optional<std::int64_t> address_failure) {
  if (DbStatus s = store.delete_login_failures_of(account_key(username)); !s.ok()) return s;
  if (address_failure) return store.delete_login_failure(*address_failure);
  return {};
}

}  // namespace ricochet::db
