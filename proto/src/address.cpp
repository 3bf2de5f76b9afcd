#include "ricochet/proto/address.h"

#include <algorithm>
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

HostKey host_key(const Address& address) {
  HostKey key;
  constexpr std::array<std::uint8_t, 12> kMappedV4 = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0xff, 0xff};
  if (!address.v6) {
    std::copy_n(address.ip.begin(), 4, key.bytes.begin());
  } else if (std::equal(kMappedV4.begin(), kMappedV4.end(), address.ip.begin())) {
    std::copy_n(address.ip.begin() + 12, 4, key.bytes.begin());
  } else {
    std::copy_n(address.ip.begin(), 8, key.bytes.begin());
    key.v6 = true;
  }
  return key;
}

std::string HostKey::to_string() const {
  char text[64];
  if (!v6) {
    std::snprintf(text, sizeof text, "%u.%u.%u.%u", bytes[0], bytes[1], bytes[2], bytes[3]);
    return text;
  }
  std::string out;
  for (int group = 0; group < 4; ++group) {
    std::snprintf(text, sizeof text, group ? ":%x" : "%x",
                  (bytes[2 * group] << 8) | bytes[2 * group + 1]);
    out += text;
  }
  return out + "::/64";
}

std::size_t HostKeyHash::operator()(const HostKey& key) const noexcept {
  Address as_address;
  as_address.ip = key.bytes;
  as_address.v6 = key.v6;
  return AddressHash{}(as_address);
}

}  // namespace ricochet::proto
