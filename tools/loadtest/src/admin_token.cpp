#include "ricochet/loadtest/admin_token.h"

#include <fstream>

namespace ricochet::loadtest {

std::string parse_admin_token(std::string_view bytes, std::string& token) {
  constexpr std::string_view kWhitespace = " \t\r\n";
  const std::size_t first = bytes.find_first_not_of(kWhitespace);
  if (first == std::string_view::npos) return "is empty; write the servers' admin token into it";
  const std::string_view trimmed =
      bytes.substr(first, bytes.find_last_not_of(kWhitespace) - first + 1);
  for (std::size_t i = 0; i < trimmed.size(); ++i) {
    const auto byte = static_cast<unsigned char>(trimmed[i]);
    if (byte < 0x20 || byte > 0x7e) {
      return "has byte " + std::to_string(byte) + " at " + std::to_string(first + i) +
             "; a token is printable ASCII on one line";
    }
  }
  token = std::string(trimmed);
  return {};
}

std::string read_admin_token(const std::string& path, std::string& token) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return "cannot read the admin token file " + path;
  std::string bytes(kMaxAdminTokenBytes + 1, '\0');
  file.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (file.bad()) return "cannot read the admin token file " + path;
  bytes.resize(static_cast<std::size_t>(file.gcount()));
  if (bytes.size() > kMaxAdminTokenBytes) {
    return "the admin token file " + path + " is larger than " +
           std::to_string(kMaxAdminTokenBytes) + " bytes";
  }
  if (std::string problem = parse_admin_token(bytes, token); !problem.empty()) {
    return "the admin token file " + path + " " + problem;
  }
  return {};
}

}  // namespace ricochet::loadtest
