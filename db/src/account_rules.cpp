/// Name and password rules (account_rules.h).

#include "account_rules.h"

#include <algorithm>

#include "ricochet/db/accounts.h"

namespace ricochet::db {

namespace {

constexpr std::size_t kMinUsername = 3;
constexpr std::size_t kMaxUsername = 24;
constexpr std::size_t kMaxShown = 40;  ///< characters of a name shown in a message

bool allowed_in_username(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
         c == '-' || c == '.';
}

}  // namespace

std::string username_key(std::string_view username) {
  std::string out(username);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) {
    return static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
  });
  return out;
}

std::string printable(std::string_view text) {
  static constexpr const char* kDigits = "0123456789abcdef";
  std::string out;
  for (const char c : text.substr(0, kMaxShown)) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u < 0x7f) {
      out += c;
    } else {
      out += "\\x";
      out += kDigits[u >> 4];
      out += kDigits[u & 15];
    }
  }
  if (text.size() > kMaxShown) out += "...";
  return out;
}

DbStatus check_username(std::string_view username) {
  if (username.size() < kMinUsername || username.size() > kMaxUsername) {
    return DbError{DbErrorCode::InvalidUsername, "username must be 3-24 characters, got " +
                                                     std::to_string(username.size()) + " ('" +
                                                     printable(username) + "')"};
  }
  if (!std::all_of(username.begin(), username.end(), allowed_in_username)) {
    return DbError{DbErrorCode::InvalidUsername,
                   "username may hold only letters, digits, '_', '-' and '.', got '" +
                       printable(username) + "'"};
  }
  return {};
}

DbStatus check_password_length(std::size_t bytes, std::size_t min_bytes, std::string_view what) {
  const std::string name(what);
  if (bytes > kMaxPasswordBytes) {
    return DbError{DbErrorCode::PasswordTooLong, name + " must be at most " +
                                                     std::to_string(kMaxPasswordBytes) +
                                                     " bytes, got " + std::to_string(bytes)};
  }
  if (bytes == 0 && min_bytes > 0)
    return DbError{DbErrorCode::EmptyPassword, name + " must not be empty"};
  if (bytes < min_bytes) {
    return DbError{DbErrorCode::PasswordTooShort, name + " must be at least " +
                                                      std::to_string(min_bytes) + " bytes, got " +
                                                      std::to_string(bytes)};
  }
  return {};
}

}  // namespace ricochet::db
