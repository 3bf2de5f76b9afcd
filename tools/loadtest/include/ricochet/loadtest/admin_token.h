#pragma once
/// The bearer token a server's admin port wants on /metrics (the server's admin.token_file,
/// `--admin-token-file`), read from a file the operator gives: untrusted bytes, bounded and
/// checked, because they go into every scrape's request header.

#include <cstddef>
#include <string>
#include <string_view>

namespace ricochet::loadtest {

/// The largest token file read, bytes (a token is tens of bytes).
inline constexpr std::size_t kMaxAdminTokenBytes = 4096;

/// The token in `bytes` into `token`: surrounding whitespace dropped (the trailing newline of
/// an editor or `echo`, as the server drops it). Empty when usable; otherwise why not (empty, a
/// control or non-ASCII byte, which would break or forge the request's header).
std::string parse_admin_token(std::string_view bytes, std::string& token);

/// The token in the file at `path` into `token` (at most kMaxAdminTokenBytes read); empty when
/// usable, otherwise why not, naming the file.
std::string read_admin_token(const std::string& path, std::string& token);

}  // namespace ricochet::loadtest
