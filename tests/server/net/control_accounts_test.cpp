// The control channel over real TLS sockets: register, login, wrong password, resume on a new
// connection, pinning by fingerprint, ping; the account limits seen from other hosts (clients
// connect from 127.0.0.2, 127.0.0.3 ... to be other addresses to the server).

#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include <sstream>

#include "control_test_client.h"
#include "episode_log.h"

namespace ricochet::server::test::control_accounts_test {
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

// Issue 29: there was no way to end a session but to let it expire.
TEST(ControlAccounts, LogoutRevokesTheSessionLeavesTheMatchAndAllowsANewLogin) {
  ControlRig rig;
  ControlTestClient client(rig.port());
  ASSERT_TRUE(client.connect());
  const wire::SessionReply session = client.sign_in("ada");
  ASSERT_TRUE(client.request(ControlTestClient::join(1)).has_join_match());
  ASSERT_TRUE(rig.directory().seated(session.account_id()));

  const auto reply = client.request(ControlTestClient::logout());
  EXPECT_TRUE(reply.has_logout()) << reply.DebugString();
  EXPECT_EQ(client.protocol().state(), proto::ControlState::Unauthenticated);
  EXPECT_FALSE(rig.directory().seated(session.account_id()));
  EXPECT_EQ(client.request(ControlTestClient::list_matches()).error().code(), wire::WRONG_STATE);

  ControlTestClient elsewhere(rig.port());
  ASSERT_TRUE(elsewhere.connect());
  EXPECT_EQ(elsewhere.request(ControlTestClient::resume(session.session_token())).error().code(),
            wire::UNKNOWN_SESSION);
  EXPECT_TRUE(client.request(ControlTestClient::login("ada", "password-ada")).has_session());
}

// Issue 29: five wrong passwords a minute from anywhere used to lock the account everywhere.
TEST(ControlAccounts, AGuesserIsStoppedAndTheOwnerStillLogsInFromItsOwnAddress) {
  ControlRig rig;
  ControlTestClient owner(rig.port());
  owner.use_source("127.0.0.3");
  ASSERT_TRUE(owner.connect());
  ASSERT_TRUE(owner.request(ControlTestClient::register_account("victim", "password-victim"))
                  .has_register_account());

  ControlTestClient guesser(rig.port());
  guesser.use_source("127.0.0.2");
  ASSERT_TRUE(guesser.connect());
  int wrong = 0;
  int limited = 0;
  for (int i = 0; i < 8; ++i) {
    const auto reply =
        guesser.request(ControlTestClient::login("victim", "guess-" + std::to_string(i)));
    if (reply.error().code() == wire::WRONG_CREDENTIALS) ++wrong;
    if (reply.error().code() == wire::LOGIN_RATE_LIMITED) ++limited;
  }
  EXPECT_EQ(wrong, 5);  // the guesser is limited ...
  EXPECT_EQ(limited, 3);
  EXPECT_TRUE(rig.wait_refusals(ControlRefusal::LoginRateLimited, 3));
  // ... and even with the right password, from its address.
  EXPECT_EQ(guesser.request(ControlTestClient::login("victim", "password-victim")).error().code(),
            wire::LOGIN_RATE_LIMITED);

  // The owner, at once, from its own address.
  const auto reply = owner.request(ControlTestClient::login("victim", "password-victim"));
  EXPECT_TRUE(reply.has_session()) << reply.DebugString();
}

// Issue 29: registration had no limit, so one address could create accounts without end.
TEST(ControlAccounts, RegistrationsFromOneAddressAreLimitedWhileAnotherRegisters) {
  db::AccountsOptions accounts;
  accounts.registrations_per_address = {3, 3'600'000};
  ControlRig rig({}, {}, accounts);
  ControlTestClient flooder(rig.port());
  flooder.use_source("127.0.0.2");
  ASSERT_TRUE(flooder.connect());
  int registered = 0;
  int limited = 0;
  for (int i = 0; i < 10; ++i) {
    const auto reply = flooder.request(
        ControlTestClient::register_account("bot" + std::to_string(i), "password-bot"));
    if (reply.has_register_account()) ++registered;
    if (reply.error().code() == wire::REGISTRATION_RATE_LIMITED) ++limited;
  }
  EXPECT_EQ(registered, 3);
  EXPECT_EQ(limited, 7);
  EXPECT_TRUE(rig.wait_refusals(ControlRefusal::RegistrationRateLimited, 7));
  // A second connection from the same address is the same address.
  ControlTestClient same(rig.port());
  same.use_source("127.0.0.2");
  ASSERT_TRUE(same.connect());
  EXPECT_EQ(
      same.request(ControlTestClient::register_account("bot99", "password-bot")).error().code(),
      wire::REGISTRATION_RATE_LIMITED);

  ControlTestClient player(rig.port());
  player.use_source("127.0.0.3");
  ASSERT_TRUE(player.connect());
  const auto reply = player.request(ControlTestClient::register_account("ada", "lovelace1"));
  EXPECT_TRUE(reply.has_register_account()) << reply.DebugString();
  EXPECT_TRUE(player.request(ControlTestClient::login("ada", "lovelace1")).has_session());
}

// Issue 29: the account refusals were counted but not logged, so an operator saw the counter
// climb without knowing from where; logging each one would let an attacker flood the log.
TEST(ControlAccounts, AccountRefusalsAreLoggedOncePerEpisodeAndAddress) {
  std::ostringstream lines;
  auto previous = spdlog::default_logger();
  auto capture = std::make_shared<spdlog::logger>(
      "capture", std::make_shared<spdlog::sinks::ostream_sink_mt>(lines));
  capture->set_level(spdlog::level::warn);
  capture->set_pattern("%v");
  spdlog::set_default_logger(capture);
  {
    EpisodeLog episodes;
    db::AccountsOptions accounts;
    accounts.registrations_per_address = {2, 3'600'000};
    accounts.per_account_address = {{2, 60'000}};
    ControlRig rig({}, {}, accounts, &episodes);
    ControlTestClient flooder(rig.port());
    flooder.use_source("127.0.0.2");
    ASSERT_TRUE(flooder.connect());
    for (int i = 0; i < 12; ++i) {
      (void)flooder.request(
          ControlTestClient::register_account("bot" + std::to_string(i), "password-bot"));
    }
    for (int i = 0; i < 12; ++i) {
      (void)flooder.request(ControlTestClient::login("bot0", "wrong-password"));
    }
    EXPECT_TRUE(rig.wait_refusals(ControlRefusal::RegistrationRateLimited, 10));
    EXPECT_TRUE(rig.wait_refusals(ControlRefusal::LoginRateLimited, 10));
    ControlTestClient other(rig.port());
    other.use_source("127.0.0.3");
    ASSERT_TRUE(other.connect());
    for (int i = 0; i < 4; ++i) {
      (void)other.request(
          ControlTestClient::register_account("other" + std::to_string(i), "password-bot"));
    }
    EXPECT_TRUE(rig.wait_refusals(ControlRefusal::RegistrationRateLimited, 12));
  }
  spdlog::set_default_logger(previous);
  const std::string text = lines.str();
  const auto count = [&text](const std::string& what) {
    std::size_t n = 0;
    for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
  };
  // 10 + 2 registrations and 10 logins refused: one line per (reason, address).
  EXPECT_EQ(count("registration_rate_limited from 127.0.0.2:"), 1u) << text;
  EXPECT_EQ(count("registration_rate_limited from 127.0.0.3:"), 1u) << text;
  EXPECT_EQ(count("login_rate_limited from 127.0.0.2:"), 1u) << text;
  EXPECT_EQ(count("registration_rate_limited"), 2u) << text;
}

}  // namespace
}  // namespace ricochet::server::test::control_accounts_test
