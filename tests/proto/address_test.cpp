#include "ricochet/proto/address.h"

#include <gtest/gtest.h>

namespace ricochet::proto::address_test {
namespace {

Address ipv6(std::array<std::uint8_t, 16> ip, std::uint16_t port) {
  Address address;
  address.ip = ip;
  address.port = port;
  address.v6 = true;
  return address;
}

TEST(HostKey, AnIpv4AddressIsItsKeyWhateverThePort) {
  const HostKey key = host_key(Address::ipv4(10, 1, 2, 3, 4000));
  EXPECT_EQ(key, host_key(Address::ipv4(10, 1, 2, 3, 5000)));
  EXPECT_NE(key, host_key(Address::ipv4(10, 1, 2, 4, 4000)));
  EXPECT_EQ(key.to_string(), "10.1.2.3");
}

TEST(HostKey, AnIpv6AddressCountsUnderItsSlash64) {
  const HostKey key =
      host_key(ipv6({0x20, 0x01, 0x0d, 0xb8, 0, 1, 0, 2, 0xaa, 0xbb, 0, 0, 0, 0, 0, 1}, 9));
  EXPECT_EQ(key, host_key(ipv6({0x20, 0x01, 0x0d, 0xb8, 0, 1, 0, 2, 1, 2, 3, 4, 5, 6, 7, 8}, 10)));
  EXPECT_NE(key,
            host_key(ipv6({0x20, 0x01, 0x0d, 0xb8, 0, 1, 0, 3, 0xaa, 0xbb, 0, 0, 0, 0, 0, 1}, 9)));
  EXPECT_EQ(key.to_string(), "2001:db8:1:2::/64");
  EXPECT_EQ(HostKeyHash{}(key),
            HostKeyHash{}(
                host_key(ipv6({0x20, 0x01, 0x0d, 0xb8, 0, 1, 0, 2, 9, 9, 9, 9, 9, 9, 9, 9}, 1))));
}

TEST(HostKey, AnIpv4MappedIpv6AddressIsItsIpv4Address) {
  const HostKey key = host_key(ipv6({0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0xff, 0xff, 127, 0, 0, 1}, 7));
  EXPECT_EQ(key, host_key(Address::ipv4(127, 0, 0, 1, 8)));
  EXPECT_FALSE(key.v6);
}

TEST(HostKey, AnIpv4AndAnIpv6KeyWithTheSameBytesDiffer) {
  EXPECT_NE(host_key(Address::ipv4(32, 1, 13, 184, 1)),
            host_key(ipv6({32, 1, 13, 184, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1}, 1)));
}

}  // namespace
}  // namespace ricochet::proto::address_test
