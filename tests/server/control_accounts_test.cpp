// The control channel over real TLS sockets: register, login, wrong password, resume on a new
// connection, pinning by fingerprint, ping.

#include <gtest/gtest.h>

#include "control_test_client.h"

namespace ricochet::server::test {
namespace {

TEST(ControlAccounts, NegotiatesTls13AndPresentsThePinnedCertificate) {
  ControlRig rig;
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  EXPECT_EQ(client.negotiated_version(), "TLSv1.3");
  EXPECT_EQ(client.peer_fingerprint(), rig.server().identity().fingerprint_sha256);
  EXPECT_TRUE(rig.server().identity().generated);
}

TEST(ControlAccounts, RegisterThenLoginGivesASession) {
  ControlRig rig;
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  const auto registered = client.request(ControlTestClient::register_account("ada", "lovelace1"));
  ASSERT_TRUE(registered.has_register_account()) << registered.DebugString();
  EXPECT_GT(registered.register_account().account_id(), 0u);

  const auto login = client.request(ControlTestClient::login("ada", "lovelace1"));
  ASSERT_TRUE(login.has_session()) << login.DebugString();
  EXPECT_EQ(login.session().account_id(), registered.register_account().account_id());
  EXPECT_EQ(login.session().username(), "ada");
  EXPECT_EQ(login.session().session_token().size(), 64u);
  EXPECT_GT(login.session().expires_unix_ms(), 0);
}

TEST(ControlAccounts, DuplicateAndInvalidRegistrationsAreErrors) {
  ControlRig rig;
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  ASSERT_TRUE(client.request(ControlTestClient::register_account("ada", "lovelace1"))
                  .has_register_account());
  auto reply = client.request(ControlTestClient::register_account("ADA", "lovelace2"));
  EXPECT_EQ(reply.error().code(), wire::DUPLICATE_USERNAME) << reply.DebugString();
  reply = client.request(ControlTestClient::register_account("a", "lovelace2"));
  EXPECT_EQ(reply.error().code(), wire::INVALID_USERNAME) << reply.DebugString();
  reply = client.request(ControlTestClient::register_account("grace", "short"));
  EXPECT_EQ(reply.error().code(), wire::INVALID_PASSWORD) << reply.DebugString();
  EXPECT_FALSE(reply.error().message().empty());
}

TEST(ControlAccounts, WrongPasswordIsRefusedAndTheConnectionStaysUnauthenticated) {
  ControlRig rig;
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  ASSERT_TRUE(client.request(ControlTestClient::register_account("ada", "lovelace1"))
                  .has_register_account());
  auto reply = client.request(ControlTestClient::login("ada", "wrong-password"));
  EXPECT_EQ(reply.error().code(), wire::WRONG_CREDENTIALS) << reply.DebugString();
  reply = client.request(ControlTestClient::login("nobody", "lovelace1"));
  EXPECT_EQ(reply.error().code(), wire::WRONG_CREDENTIALS) << reply.DebugString();
  // Still unauthenticated: a match request is out of state; the right password still works.
  reply = client.request(ControlTestClient::join(1));
  EXPECT_EQ(reply.error().code(), wire::WRONG_STATE);
  EXPECT_TRUE(client.request(ControlTestClient::login("ada", "lovelace1")).has_session());
}

TEST(ControlAccounts, ResumeOnANewConnectionRestoresTheAccount) {
  ControlRig rig;
  std::string token;
  std::uint64_t account = 0;
  {
    ControlTestClient first(rig.port());
    ASSERT_TRUE(first.connect());
    const wire::SessionReply session = first.sign_in("ada");
    token = session.session_token();
    account = session.account_id();
  }
  ControlTestClient second(rig.port());
  ASSERT_TRUE(second.connect());
  const auto reply = second.request(ControlTestClient::resume(token));
  ASSERT_TRUE(reply.has_session()) << reply.DebugString();
  EXPECT_EQ(reply.session().account_id(), account);
  EXPECT_EQ(reply.session().username(), "ada");
  EXPECT_TRUE(reply.session().session_token().empty());
  // Authenticated now: the match list is allowed.
  EXPECT_TRUE(second.request(ControlTestClient::list_matches()).has_list_matches());
}

TEST(ControlAccounts, ResumeWithAnUnknownTokenIsRefused) {
  ControlRig rig;
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  auto reply = client.request(ControlTestClient::resume(std::string(64, 'a')));
  EXPECT_EQ(reply.error().code(), wire::UNKNOWN_SESSION) << reply.DebugString();
  reply = client.request(ControlTestClient::resume("not hex"));
  EXPECT_EQ(reply.error().code(), wire::UNKNOWN_SESSION) << reply.DebugString();
}

TEST(ControlAccounts, PingIsAnsweredInEveryStateWithItsTime) {
  ControlRig rig;
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  auto reply = client.request(ControlTestClient::ping(12345));
  ASSERT_TRUE(reply.has_pong());
  EXPECT_EQ(reply.pong().client_time_us(), 12345u);
  EXPECT_GT(reply.pong().server_unix_ms(), 0);
  client.sign_in("ada");
  EXPECT_TRUE(client.request(ControlTestClient::ping(1)).has_pong());
}

TEST(ControlAccounts, LoginAgainOnALoggedInConnectionIsWrongState) {
  ControlRig rig;
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  client.sign_in("ada");
  const auto reply = client.request(ControlTestClient::login("ada", "password-ada"));
  EXPECT_EQ(reply.error().code(), wire::WRONG_STATE);
  EXPECT_NE(reply.error().message().find("authenticated"), std::string::npos)
      << reply.error().message();
  EXPECT_EQ(rig.refusals(ControlRefusal::WrongState), 1u);
}

}  // namespace
}  // namespace ricochet::server::test
