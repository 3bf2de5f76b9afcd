#pragma once
/// The rate limits of logins and registrations (accounts.h), kept in the store so that every
/// server process on one database enforces one limit. Events are noted under keys:
///
///   "account:<username key>"                       failed logins of an account, any address
///   "account-address:<username key> <address>"     failed logins of an account from an address
///   "address:<address>"                            failed logins from an address, any account
///   "registration:<address>"                       registrations from an address
///
/// <address> is what the caller names the client by (the server passes proto::host_key: an
/// IPv4 address or an IPv6 /64); a username key has no space, so the keys cannot collide.

#include <cstdint>
#include <string_view>
#include <vector>

#include "ricochet/db/accounts.h"
#include "ricochet/db/store.h"

namespace ricochet::db {

/// RateLimited when the account from this address, the account from everywhere or the address
/// already has its limit of failures within the window; otherwise notes a failure under each
/// (an attempt counts as failed until it succeeds, so attempts in flight at once cannot slip
/// past together) and returns the ids of the notes that forgive_login takes back. An empty
/// `address` skips the limits that name it. Runs in one transaction, and drops events older
/// than every window on the way.
DbResult<std::vector<std::int64_t>> admit_login(Store& store, const AccountsOptions& options,
                                                std::string_view username, std::string_view address,
                                                UnixMillis now);

/// After a successful login: forgets the failures of the account from this address (the
/// owner's own typos) and the notes this attempt made; the failures other addresses caused
/// stay counted. Call inside the login's transaction.
DbStatus forgive_login(Store& store, std::string_view username, std::string_view address,
                       const std::vector<std::int64_t>& noted);

/// RateLimited when the address registered its limit of accounts within the window; otherwise
/// notes this registration. An empty `address` is not limited. One transaction.
DbStatus admit_registration(Store& store, const AccountsOptions& options, std::string_view address,
                            UnixMillis now);

}  // namespace ricochet::db
