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

}  // namespace ricochet::proto
