/// Picks the backend by the form of the URL (store.h).

#include "ricochet/db/store.h"

namespace ricochet::db {

bool is_postgres_url(std::string_view url_or_path) {
  return url_or_path.starts_with("postgresql://") || url_or_path.starts_with("postgres://");
}

DbResult<std::unique_ptr<Store>> open_store(const StoreOptions& options) {
  if (is_postgres_url(options.url_or_path))
    return open_postgres_store(
        PostgresOptions{.url = options.url_or_path, .busy_timeout_ms = options.busy_timeout_ms});
  return open_sqlite_store(
      SqliteOptions{.path = options.url_or_path, .busy_timeout_ms = options.busy_timeout_ms});
}

}  // namespace ricochet::db
