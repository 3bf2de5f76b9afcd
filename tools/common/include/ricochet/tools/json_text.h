#pragma once
/// Text for the tools' one-line JSON reports.

#include <cstdio>
#include <string>
#include <string_view>

namespace ricochet::tools {

/// `text` as a JSON string literal, quotes included: `"` and `\` escaped, control characters as
/// \u00XX.
inline std::string json_string(std::string_view text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\u%04x", static_cast<unsigned>(c));
      out += escaped;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

}  // namespace ricochet::tools
