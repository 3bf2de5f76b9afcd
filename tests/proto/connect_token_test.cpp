#include "ricochet/proto/connect_token.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace ricochet::proto::connect_token_test {
namespace {

const Key kTokenKey = [] {
  Key key{};
  key.fill(0x33);
  return key;
}();
constexpr std::uint64_t kProtocol = 0xABCD;
constexpr TimeUs kNow = 1'000 * kMicrosPerSecond;

TEST(ConnectToken, OpensToWhatWasIssued) {
  const TokenGrant grant =
      issue_connect_token(kTokenKey, kProtocol, 123456789, 7, kNow, 30 * kMicrosPerSecond, 5);
  EXPECT_EQ(grant.connect_token.size(), kConnectTokenBytes);
  EXPECT_EQ(grant.expires_at, kNow + 30 * kMicrosPerSecond);
  EXPECT_EQ(grant.timeout_s, 5u);
  EXPECT_NE(grant.client_to_server, grant.server_to_client);

  auto opened = open_connect_token(kTokenKey, kProtocol, grant.connect_token, kNow + 1);
  ASSERT_TRUE(opened.ok());
  EXPECT_EQ(opened.value.contents.account_id, 123456789u);
  EXPECT_EQ(opened.value.contents.match_id, 7u);
  EXPECT_EQ(opened.value.contents.expires_at, grant.expires_at);
  EXPECT_EQ(opened.value.contents.timeout_s, 5u);
  EXPECT_EQ(opened.value.contents.client_to_server, grant.client_to_server);
  EXPECT_EQ(opened.value.contents.server_to_client, grant.server_to_client);
  EXPECT_TRUE(std::equal(opened.value.mac.begin(), opened.value.mac.end(),
                         grant.connect_token.end() - kMacBytes));
}

TEST(ConnectToken, TwoTokensForTheSameJoinDiffer) {
  const auto a = issue_connect_token(kTokenKey, kProtocol, 1, 1, kNow, kMicrosPerSecond, 5);
  const auto b = issue_connect_token(kTokenKey, kProtocol, 1, 1, kNow, kMicrosPerSecond, 5);
  EXPECT_NE(a.connect_token, b.connect_token);
  EXPECT_NE(a.client_to_server, b.client_to_server);
}

TEST(ConnectToken, RefusesForgedWrongKeyWrongProtocolAndWrongLength) {
  const auto grant = issue_connect_token(kTokenKey, kProtocol, 1, 2, kNow, kMicrosPerSecond, 5);
  for (std::size_t i = 0; i < grant.connect_token.size(); ++i) {
    auto forged = grant.connect_token;
    forged[i] ^= 0x01;
    EXPECT_EQ(open_connect_token(kTokenKey, kProtocol, forged, kNow).error,
              DropReason::TokenInvalid)
        << "byte " << i;
  }
  Key other = kTokenKey;
  other[31] ^= 1;
  EXPECT_EQ(open_connect_token(other, kProtocol, grant.connect_token, kNow).error,
            DropReason::TokenInvalid);
  EXPECT_EQ(open_connect_token(kTokenKey, kProtocol + 1, grant.connect_token, kNow).error,
            DropReason::TokenInvalid);
  std::vector<std::uint8_t> shorter(grant.connect_token.begin(), grant.connect_token.end() - 1);
  EXPECT_EQ(open_connect_token(kTokenKey, kProtocol, shorter, kNow).error, DropReason::Malformed);
}

TEST(ConnectToken, ExpiresOnTheServersClock) {
  const auto grant =
      issue_connect_token(kTokenKey, kProtocol, 1, 2, kNow, 10 * kMicrosPerSecond, 5);
  EXPECT_TRUE(open_connect_token(kTokenKey, kProtocol, grant.connect_token,
                                 kNow + 10 * kMicrosPerSecond - 1)
                  .ok());
  EXPECT_EQ(
      open_connect_token(kTokenKey, kProtocol, grant.connect_token, kNow + 10 * kMicrosPerSecond)
          .error,
      DropReason::TokenExpired);
  // An expiry more than 30 s ahead is never issued: a server clock that went back is refused.
  EXPECT_EQ(
      open_connect_token(kTokenKey, kProtocol, grant.connect_token, kNow - 30 * kMicrosPerSecond)
          .error,
      DropReason::TokenExpired);
}

TEST(ConnectToken, IssuingOutsideTheLimitsIsACallersBug) {
  EXPECT_THROW(issue_connect_token(kTokenKey, kProtocol, 1, 2, kNow, 31 * kMicrosPerSecond, 5),
               std::invalid_argument);
  EXPECT_THROW(issue_connect_token(kTokenKey, kProtocol, 1, 2, kNow, 0, 5), std::invalid_argument);
  EXPECT_THROW(issue_connect_token(kTokenKey, kProtocol, 1, 2, kNow, kMicrosPerSecond, 0),
               std::invalid_argument);
  EXPECT_THROW(issue_connect_token(kTokenKey, kProtocol, 1, 2, kNow, kMicrosPerSecond, 61),
               std::invalid_argument);
}

TEST(ConnectTokenPlaintext, RoundTripsAndRefusesBadTimeoutsAndLengths) {
  ConnectTokenContents contents;
  contents.account_id = 9;
  contents.match_id = 3;
  contents.expires_at = 77;
  contents.timeout_s = 5;
  contents.client_to_server[0] = 1;
  contents.server_to_client[0] = 2;
  auto plain = encode_connect_token_plaintext(contents);
  EXPECT_EQ(plain.size(), kConnectTokenPlainBytes);
  auto decoded = decode_connect_token_plaintext(plain);
  ASSERT_TRUE(decoded.ok());
  EXPECT_EQ(decoded.value, contents);
  contents.timeout_s = 0;
  EXPECT_FALSE(decode_connect_token_plaintext(encode_connect_token_plaintext(contents)).ok());
  plain.pop_back();
  EXPECT_FALSE(decode_connect_token_plaintext(plain).ok());
}

}  // namespace
}  // namespace ricochet::proto::connect_token_test
