#pragma once
/// The name and password rules of Accounts (accounts.h), each written once.

#include <cstddef>
#include <string>
#include <string_view>

#include "ricochet/db/result.h"

namespace ricochet::db {

/// The form a username is unique in: ASCII letters lowercased.
std::string username_key(std::string_view username);
/// A name as it may appear in a message: printable ASCII kept, the rest escaped, truncated.
std::string printable(std::string_view text);
/// InvalidUsername unless 3–24 of letters, digits, '_', '-', '.'.
DbStatus check_username(std::string_view username);
/// The length rules for a password of `bytes` bytes: at most kMaxPasswordBytes, and at least
/// `min_bytes` (EmptyPassword when it is empty and min_bytes > 0). `what` names it in the
/// message ("password", "new password").
DbStatus check_password_length(std::size_t bytes, std::size_t min_bytes, std::string_view what);

}  // namespace ricochet::db
