/// Names of the error codes (result.h).

#include "ricochet/db/result.h"

namespace ricochet::db {

const char* to_string(DbErrorCode code) {
  switch (code) {
    case DbErrorCode::InvalidUsername:
      return "invalid_username";
    case DbErrorCode::DuplicateUsername:
      return "duplicate_username";
    case DbErrorCode::EmptyPassword:
      return "empty_password";
    case DbErrorCode::PasswordTooShort:
      return "password_too_short";
    case DbErrorCode::PasswordTooLong:
      return "password_too_long";
    case DbErrorCode::WrongCredentials:
      return "wrong_credentials";
    case DbErrorCode::AccountBanned:
      return "account_banned";
    case DbErrorCode::UnknownAccount:
      return "unknown_account";
    case DbErrorCode::UnknownSession:
      return "unknown_session";
    case DbErrorCode::ExpiredSession:
      return "expired_session";
    case DbErrorCode::RateLimited:
      return "rate_limited";
    case DbErrorCode::InvalidMatch:
      return "invalid_match";
    case DbErrorCode::InvalidPlacement:
      return "invalid_placement";
    case DbErrorCode::NoServerAvailable:
      return "no_server_available";
    case DbErrorCode::UnknownModeOrMap:
      return "unknown_mode_or_map";
    case DbErrorCode::UnknownTicket:
      return "unknown_ticket";
    case DbErrorCode::ExpiredTicket:
      return "expired_ticket";
    case DbErrorCode::SchemaTooNew:
      return "schema_too_new";
    case DbErrorCode::CorruptDatabase:
      return "corrupt_database";
    case DbErrorCode::CannotOpen:
      return "cannot_open";
    case DbErrorCode::Busy:
      return "busy";
    case DbErrorCode::Unavailable:
      return "unavailable";
    case DbErrorCode::QueueFull:
      return "queue_full";
    case DbErrorCode::Storage:
      return "storage";
    case DbErrorCode::OutOfMemory:
      return "out_of_memory";
    case DbErrorCode::Stopped:
      return "stopped";
  }
  return "unknown";
}

}  // namespace ricochet::db
