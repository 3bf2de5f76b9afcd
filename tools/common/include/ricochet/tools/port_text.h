#pragma once
/// A TCP or UDP port written in text, as the tools' options and the assignments of placement
/// give it.

#include <charconv>
#include <cstdint>
#include <optional>
#include <string_view>
#include <system_error>

namespace ricochet::tools {

/// The port 1..65535 that is all of `text` (decimal digits only); nullopt otherwise.
inline std::optional<std::uint16_t> parse_port(std::string_view text) {
  unsigned value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc{} || end != text.data() + text.size() || value == 0 || value > 65535) {
    return std::nullopt;
  }
  return static_cast<std::uint16_t>(value);
}

}  // namespace ricochet::tools
