#include "admin_signin_limiter.h"

#include <gtest/gtest.h>

#include <cstdint>

namespace ricochet::server::admin_signin_limiter_test {
namespace {

constexpr proto::TimeUs kSecond = proto::kMicrosPerSecond;

proto::HostKey ipv4(std::uint32_t address) {
  proto::HostKey key;
  for (int i = 0; i < 4; ++i) key.bytes[i] = static_cast<std::uint8_t>(address >> (24 - 8 * i));
  return key;
}

TEST(AdminSignInLimiter, AnAddressWaitsFromItsLastAllowedFailureToTheEndOfItsWindow) {
  AdminSignInLimiter limiter{2, 60 * kSecond, 16};
  const proto::HostKey guesser = ipv4(0x0a000001);
  limiter.fail(guesser, 10 * kSecond);
  EXPECT_EQ(limiter.wait_us(guesser, 10 * kSecond), 0);
  limiter.fail(guesser, 30 * kSecond);
  EXPECT_EQ(limiter.wait_us(guesser, 30 * kSecond), 40 * kSecond);
  EXPECT_EQ(limiter.wait_us(ipv4(0x0a000002), 30 * kSecond), 0);
  EXPECT_EQ(limiter.wait_us(guesser, 70 * kSecond), 0);
  // A failure after the window opens a new one.
  limiter.fail(guesser, 70 * kSecond);
  EXPECT_EQ(limiter.wait_us(guesser, 70 * kSecond), 0);
  limiter.fail(guesser, 71 * kSecond);
  EXPECT_EQ(limiter.wait_us(guesser, 71 * kSecond), 59 * kSecond);
}

TEST(AdminSignInLimiter, ASprayOfAddressesKeepsTheTableBoundedAndForgetsTheOldestFirst) {
  AdminSignInLimiter limiter{1, 60 * kSecond, 8};
  const proto::HostKey victim_of_eviction = ipv4(1);
  limiter.fail(victim_of_eviction, 0);
  const proto::HostKey second = ipv4(2);
  limiter.fail(second, 1);
  for (std::uint32_t i = 0; i < 10'000; ++i) {
    limiter.fail(ipv4(1'000 + i), 2 + i);
    ASSERT_LE(limiter.addresses(), 8U);
  }
  EXPECT_EQ(limiter.wait_us(victim_of_eviction, 20'000), 0);
  EXPECT_EQ(limiter.wait_us(second, 20'000), 0);
  // The newest are still held.
  EXPECT_GT(limiter.wait_us(ipv4(1'000 + 9'999), 20'000), 0);
}

}  // namespace
}  // namespace ricochet::server::admin_signin_limiter_test
