#pragma once
/// The PostgreSQL schema as numbered migrations, numbered like SQLite's (migrations.h): version N
/// holds the same tables and indexes in both. The version is the one row of schema_version (a
/// database without that table is version 0). postgres_schema_version() (store.h) is the last.

#include <libpq-fe.h>

#include <span>
#include <string>

#include "migrations.h"
#include "ricochet/db/result.h"

namespace ricochet::db {

/// Every PostgreSQL migration, in order.
std::span<const Migration> postgres_migrations();

/// The database's schema version. SchemaTooNew when a newer Ricochet wrote it; only read.
/// `where` names the database in messages.
DbResult<int> read_postgres_schema_version(PGconn* conn, const std::string& where);

/// Applies every migration above the database's version, each in a transaction that holds the
/// write lock (postgres::kWriteLockKey) and re-reads the version, so servers starting at the
/// same moment apply each migration once.
DbStatus apply_postgres_migrations(PGconn* conn, const std::string& where);

}  // namespace ricochet::db
