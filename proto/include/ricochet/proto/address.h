#pragma once
/// A UDP peer's address as the sans-IO endpoints see it: bytes, not a socket type, so proto/
/// knows no sockets. The Asio layer converts to and from asio::ip::udp::endpoint.

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>

namespace ricochet::proto {

struct Address {
  /// IPv4 in the first 4 bytes (v6 == false), or 16 bytes of IPv6; the rest zero.
  std::array<std::uint8_t, 16> ip{};
  std::uint16_t port = 0;
  bool v6 = false;

  static Address ipv4(std::uint8_t a, std::uint8_t b, std::uint8_t c, std::uint8_t d,
                      std::uint16_t port);
  /// "1.2.3.4:5" or "[::1]:5".
  std::string to_string() const;
  friend bool operator==(const Address&, const Address&) = default;
};

struct AddressHash {
  std::size_t operator()(const Address& address) const noexcept;
};

/// What every per-address limit of the server counts under (PROTOCOL.md "Limits and
/// addresses"): an IPv4 address without its port, or the /64 prefix of an IPv6 address (one
/// subscriber is usually given a whole /64, so counting single IPv6 addresses limits nothing).
/// An IPv4-mapped IPv6 address (::ffff:a.b.c.d) is its IPv4 address.
struct HostKey {
  std::array<std::uint8_t, 16> bytes{};  ///< 4 bytes of IPv4 or 8 of an IPv6 prefix; rest zero
  bool v6 = false;

  /// "1.2.3.4" or "2001:db8:0:1::/64": what logs and the store's limit keys show.
  std::string to_string() const;
  friend bool operator==(const HostKey&, const HostKey&) = default;
};

HostKey host_key(const Address& address);

struct HostKeyHash {
  std::size_t operator()(const HostKey& key) const noexcept;
};

}  // namespace ricochet::proto
