#pragma once
/// Failed-login rate limits (accounts.h), kept in the store so that every server process on one
/// database enforces one limit. Failures are noted under "account:<username key>" and
/// "address:<client address>".

#include <cstdint>
#include <optional>
#include <string_view>

#include "ricochet/db/accounts.h"
#include "ricochet/db/store.h"

namespace ricochet::db {

/// RateLimited when the account or the address already has its limit of failures within the
/// window; otherwise notes a failure under each (an attempt counts as failed until it
/// succeeds, so attempts in flight at once cannot slip past together) and returns the id of
/// the address's, nullopt when `address` is empty. Runs in one transaction, and drops
/// failures older than both windows on the way.
DbResult<std::optional<std::int64_t>> admit_login(Store& store, const AccountsOptions& options,
                                                  std::string_view username,
                                                  std::string_view address, UnixMillis now);

/// After a successful login: forgets every failure of the account, and the one failure its
/// attempt noted under the address. Call inside the login's transaction.
DbStatus forgive_login(Store& store, std::string_view username,
                       std::optional<std::int64_t> address_failure);

}  // namespace ricochet::db
