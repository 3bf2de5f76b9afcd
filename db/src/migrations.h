#pragma once
/// The SQLite schema as numbered migrations under PRAGMA user_version. Migration N takes a file
/// from version N-1 to N in its own transaction; a released migration is never edited, only
/// followed by a new one. sqlite_schema_version() (store.h) is the last number.

#include <sqlite3.h>

#include <span>
#include <string>

#include "ricochet/db/result.h"

namespace ricochet::db {

struct Migration {
  int version;          ///< the user_version after this migration: 1, 2, …
  const char* summary;  ///< one line for logs and error messages
  const char* sql;      ///< one or more statements, run inside the migration's transaction
};

/// Every migration, in order.
std::span<const Migration> sqlite_migrations();

/// The file's user_version. SchemaTooNew when a newer Ricochet wrote it; the file is only read.
/// This is the first read of the file, so it is also where a file that is not a database fails
/// (CorruptDatabase) and where an unreadable one does (CannotOpen).
DbResult<int> read_schema_version(sqlite3* db, const std::string& path);

/// Applies every migration above the file's version, each in BEGIN IMMEDIATE … COMMIT with its
/// new user_version. The version is re-read inside each transaction, so two processes opening
/// a new file at the same moment apply each migration once.
DbStatus apply_migrations(sqlite3* db, const std::string& path);

}  // namespace ricochet::db
