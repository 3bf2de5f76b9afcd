// Which admin port the directory row advertises (admin_advertisement.h): the configured one, none
// under Agones, the bound one when bound beyond loopback or when the row's host is loopback too.

#include "admin_advertisement.h"

#include <gtest/gtest.h>

namespace ricochet::server::test::admin_advertisement_test {
namespace {

AdminAdvertisement admin(const std::string& bind, const std::string& host) {
  return AdminAdvertisement{.bind = bind, .bound_port = 9100, .host = host};
}

TEST(AdminAdvertisement, ALoopbackPortIsAdvertisedOnlyToALoopbackHost) {
  EXPECT_EQ(advertised_admin_port(admin("127.0.0.1", "127.0.0.1")), 9100);
  EXPECT_EQ(advertised_admin_port(admin("127.0.0.1", "localhost")), 9100);
  EXPECT_EQ(advertised_admin_port(admin("::1", "::1")), 9100);
  EXPECT_EQ(advertised_admin_port(admin("127.0.0.1", "game1.example.net")), 0);
  EXPECT_EQ(advertised_admin_port(admin("127.0.0.1", "10.0.0.7")), 0);
}

TEST(AdminAdvertisement, APortBoundBeyondLoopbackIsAdvertised) {
  EXPECT_EQ(advertised_admin_port(admin("0.0.0.0", "game1.example.net")), 9100);
  EXPECT_EQ(advertised_admin_port(admin("::", "game1.example.net")), 9100);
  EXPECT_EQ(advertised_admin_port(admin("10.0.0.7", "10.0.0.7")), 9100);
}

TEST(AdminAdvertisement, TheConfiguredPortWinsAndAgonesAdvertisesNoneByItself) {
  AdminAdvertisement configured = admin("127.0.0.1", "game1.example.net");
  configured.configured_port = 19100;
  EXPECT_EQ(advertised_admin_port(configured), 19100);
  configured.agones = true;
  EXPECT_EQ(advertised_admin_port(configured), 19100);

  AdminAdvertisement agones = admin("0.0.0.0", "203.0.113.9");
  agones.agones = true;
  EXPECT_EQ(advertised_admin_port(agones), 0);  // the node publishes the Fleet's ports only
}

}  // namespace
}  // namespace ricochet::server::test::admin_advertisement_test
