#pragma once
/// A directory under $TMPDIR (or /tmp) removed with everything in it when the test ends; shared
/// by the db, server and integration tests.

#include <stdlib.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>

namespace ricochet::test {

class TempDir {
 public:
  /// `prefix` names the directory (e.g. "ricochet-db"), six random characters follow.
  explicit TempDir(const std::string& prefix = "ricochet") {
    std::string pattern = (std::filesystem::temp_directory_path() / (prefix + "-XXXXXX")).string();
    if (!mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed for " + pattern);
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

}  // namespace ricochet::test
