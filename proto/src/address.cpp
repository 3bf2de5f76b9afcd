#include "ricochet/proto/address.h"

#include <cstdio>

namespace ricochet::proto {

Address Address::ipv4(std::uint8_t a, std::uint8_t b, std::uint8_t c, std::uint8_t d,
                      std::uint16_t port) {
  Address address;
  address.ip = {a, b, c, d};
  address.port = port;
  return address;
}

std::string Address::to_string() const {
  char text[64];
  if (!v6) {
    std::snprintf(text, sizeof text, "%u.%u.%u.%u:%u", ip[0], ip[1], ip[2], ip[3], port);
    return text;
  }
  std::string out = "[";
  for (int group = 0; group < 8; ++group) {
    std::snprintf(text, sizeof text, group ? ":%x" : "%x",
                  (ip[2 * group] << 8) | ip[2 * group + 1]);
    out += text;
  }
  std::snprintf(text, sizeof text, "]:%u", port);
  return out + text;
}

std::size_t AddressHash::operator()(const Address& address) const noexcept {
  std::uint64_t hash = 1469598103934665603ull;  // FNV-1a over the bytes that matter
  const auto mix = [&hash](std::uint8_t byte) { hash = (hash ^ byte) * 1099511628211ull; };
  for (std::uint8_t byte : address.ip) mix(byte);
  mix(static_cast<std::uint8_t>(address.port));
  mix(static_cast<std::uint8_t>(address.port >> 8));
  mix(address.v6);
  return static_cast<std::size_t>(hash);
}

}  // namespace ricochet::proto
