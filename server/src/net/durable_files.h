#pragma once
/// Writing files that survive a crash or kill -9: every byte written, fsync()ed, and the
/// directory's entries (a new file, a rename) fsync()ed. Each call returns its error as text
/// (what failed and strerror), or empty.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace ricochet::server {

/// strerror(errno).
std::string errno_text();

/// Makes the directory's entries (a new file, a rename) durable.
std::string sync_directory(const std::filesystem::path& directory);

/// Every byte, retrying short writes and interruptions.
std::string write_all(int fd, const std::vector<std::uint8_t>& bytes);

}  // namespace ricochet::server
