/// Login and registration rate limits over the store (login_limits.h).

#include "login_limits.h"

#include <algorithm>
#include <string>

#include "account_rules.h"

namespace ricochet::db {

namespace {

std::string account_key(std::string_view username) {
  return "account:" + username_key(username);
}

std::string account_address_key(std::string_view username, std::string_view address) {
  return "account-address:" + username_key(username) + " " + std::string(address);
}

std::string address_key(std::string_view address) {
  return "address:" + std::string(address);
}

std::string registration_key(std::string_view address) {
  return "registration:" + std::string(address);
}

std::string seconds(UnixMillis ms) {
  return std::to_string(ms / 1000) + " s";
}

/// RateLimited when `key` has `limit.max_events` events within the window ending at `now`.
DbStatus check_limit(Store& store, const std::string& key, const RateLimit& limit, UnixMillis now,
                     const std::string& what) {
  const DbResult<std::int64_t> events = store.count_login_failures(key, now - limit.window_ms);
  if (!events.ok()) return events.error();
  if (events.value() < limit.max_events) return {};
  return DbError{DbErrorCode::RateLimited, std::to_string(events.value()) + " " + what +
                                               " in the last " + seconds(limit.window_ms) +
                                               "; retry later"};
}

UnixMillis longest_window(const AccountsOptions& options) {
  UnixMillis longest = std::max({options.per_account.window_ms, options.per_address.window_ms,
                                 options.registrations_per_address.window_ms});
  for (const RateLimit& step : options.per_account_address)
    longest = std::max(longest, step.window_ms);
  return longest;
}

/// Drops every event older than the longest window (it can no longer refuse anything).
DbStatus prune_limit_events(Store& store, const AccountsOptions& options, UnixMillis now) {
  return store.delete_login_failures_until(now - longest_window(options));
}

}  // namespace

DbResult<std::vector<std::int64_t>> admit_login(Store& store, const AccountsOptions& options,
                                                std::string_view username, std::string_view address,
                                                UnixMillis now) {
  using R = DbResult<std::vector<std::int64_t>>;
  std::string name = "'";  // appended, not "'" + ...: GCC 12 warns falsely (-Wrestrict) on that
  name += printable(username);
  name += '\'';
  return atomically(store, [&]() -> R {
    if (DbStatus s = prune_limit_events(store, options, now); !s.ok()) return s.error();
    std::vector<std::string> keys;
    if (!address.empty()) {
      // The guesser's own limit, in steps that allow fewer failures per minute the longer the
      // guessing goes on (a back-off); the owner from another address is not touched by it.
      const std::string pair = account_address_key(username, address);
      for (const RateLimit& step : options.per_account_address) {
        if (DbStatus s = check_limit(store, pair, step, now,
                                     "failed logins for " + name + " from " + printable(address));
            !s.ok())
          return s.error();
      }
      if (DbStatus s = check_limit(store, address_key(address), options.per_address, now,
                                   "failed logins from " + printable(address));
          !s.ok())
        return s.error();
      keys.push_back(pair);
      keys.push_back(address_key(address));
    }
    if (DbStatus s = check_limit(store, account_key(username), options.per_account, now,
                                 "failed logins for " + name + " from all addresses");
        !s.ok())
      return s.error();
    keys.push_back(account_key(username));
    std::vector<std::int64_t> noted;
    for (const std::string& key : keys) {
      DbResult<std::int64_t> id = store.insert_login_failure(key, now);
      if (!id.ok()) return id.error();
      noted.push_back(id.value());
    }
    return noted;
  });
}

DbStatus forgive_login(Store& store, std::string_view username, std::string_view address,
                       const std::vector<std::int64_t>& noted) {
  if (!address.empty()) {
    if (DbStatus s = store.delete_login_failures_of(account_address_key(username, address));
        !s.ok())
      return s;
  }
  for (const std::int64_t id : noted) {
    if (DbStatus s = store.delete_login_failure(id); !s.ok()) return s;
  }
  return {};
}

DbStatus admit_registration(Store& store, const AccountsOptions& options, std::string_view address,
                            UnixMillis now) {
  if (address.empty()) return {};
  return atomically(store, [&]() -> DbStatus {
    if (DbStatus s = prune_limit_events(store, options, now); !s.ok()) return s;
    const std::string key = registration_key(address);
    if (DbStatus s = check_limit(store, key, options.registrations_per_address, now,
                                 "accounts registered from " + printable(address));
        !s.ok())
      return s;
    DbResult<std::int64_t> noted = store.insert_login_failure(key, now);
    if (!noted.ok()) return noted.error();
    return {};
  });
}

}  // namespace ricochet::db
