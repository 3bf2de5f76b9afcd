#include "durable_files.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace ricochet::server {

std::string errno_text() {
  return std::strerror(errno);
}

std::string sync_directory(const std::filesystem::path& directory) {
  const int fd = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return "cannot open " + directory.string() + ": " + errno_text();
  std::string error;
  if (::fsync(fd) != 0) error = "cannot sync " + directory.string() + ": " + errno_text();
  ::close(fd);
  return error;
}

std::string write_all(int fd, const std::vector<std::uint8_t>& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t wrote = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (wrote < 0 && errno == EINTR) continue;
    if (wrote <= 0) return "write failed after " + std::to_string(done) + " bytes: " + errno_text();
    done += static_cast<std::size_t>(wrote);
  }
  return {};
}

}  // namespace ricochet::server
