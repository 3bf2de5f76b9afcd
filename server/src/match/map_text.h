#pragma once
/// Helpers the map readers (map_toml.cpp, map_obj.cpp) share for their error messages.

#include <string>
#include <string_view>

namespace ricochet::server::map_text {

/// Text from a map for an error message: cut to 40 characters, unprintable bytes as '?'.
inline std::string printable(std::string_view text) {
  std::string out;
  for (const char c : text.substr(0, 40)) out += (c >= 0x20 && c < 0x7f) ? c : '?';
  if (text.size() > 40) out += "...";
  return out;
}

/// The same in single quotes: 'bad/name'.
inline std::string quote(std::string_view text) {
  std::string out = "'";
  out += printable(text);
  out += '\'';
  return out;
}

}  // namespace ricochet::server::map_text
