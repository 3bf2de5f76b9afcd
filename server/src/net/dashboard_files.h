#pragma once
/// The dashboard's files (server/dashboard/), embedded in the binary at build time: the CMake
/// step server/embed_files.cmake writes them into dashboard_files.cpp in the build tree, so the
/// server needs nothing on disk to serve them and a binary always serves the pages it was built
/// with.

#include <span>
#include <string_view>

namespace ricochet::server {

struct EmbeddedFile {
  std::string_view path;          ///< from the dashboard directory: "/index.html"
  std::string_view content_type;  ///< from the extension: "text/html; charset=utf-8"
  std::string_view etag;          ///< strong, quoted: the first 32 hex digits of the SHA-256
  std::string_view bytes;
};

/// Every file of server/dashboard/, sorted by path.
std::span<const EmbeddedFile> dashboard_files();

}  // namespace ricochet::server
