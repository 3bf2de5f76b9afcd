// Accounts over both backends (a real SQLite file, a real PostgreSQL database): usernames, Argon2id
// passwords, sessions, bans, rate limits, each refusal with its own error code and a message.

#include "ricochet/db/accounts.h"

#include "db_test_util.h"
#include "password.h"
#include "test_database.h"

namespace ricochet::db::test::accounts_test {
namespace {

constexpr UnixMillis kT0 = 1'700'000'000'000;  // a fixed "now"

AccountsOptions fast_options() {
  AccountsOptions o;
  o.cost = PasswordCost::Minimum;  // tests check the rules, not Argon2id's cost
  return o;
}

class AccountsTest : public ::testing::TestWithParam<Backend> {
 protected:
  void SetUp() override { open(fast_options()); }
  void open(const AccountsOptions& options) {
    accounts_.reset();
    store_ = db_.open();
    accounts_ = std::make_unique<Accounts>(*store_, options);
  }
  Accounts& accounts() { return *accounts_; }
  AccountId register_ok(const std::string& name, const std::string& password = "correct horse") {
    return must(accounts().register_account(name, password, "", kT0), "register_account");
  }
  std::uint64_t errors(DbErrorCode code) const { return accounts_->refusals().count(code); }

  TestDatabase db_{GetParam()};
  std::unique_ptr<Store> store_;
  std::unique_ptr<Accounts> accounts_;
};

TEST_P(AccountsTest, RegisterLoginAndCheckTheSession) {
  const AccountId id = register_ok("Alice");
  const LoginResult login =
      must(accounts().login("Alice", "correct horse", "10.0.0.1", kT0 + 5), "login");
  EXPECT_EQ(login.account, id);
  EXPECT_EQ(login.token.size(), 64u);
  EXPECT_EQ(login.token.find_first_not_of("0123456789abcdef"), std::string::npos);
  EXPECT_EQ(login.expires_ms, kT0 + 5 + 24 * 3600 * 1000LL);
  const SessionInfo session = must(accounts().check_session(login.token, kT0 + 10), "check");
  EXPECT_EQ(session.account, id);
  EXPECT_EQ(session.username, "Alice");
  const Account account = must(store_->account(id), "account");
  EXPECT_EQ(account.created_ms, kT0);
  EXPECT_EQ(account.last_login_ms, kT0 + 5);
  // Two logins give two different tokens, both valid.
  const LoginResult again = must(accounts().login("alice", "correct horse", "", kT0 + 6), "login");
  EXPECT_NE(again.token, login.token);
  EXPECT_TRUE(accounts().check_session(login.token, kT0 + 10).ok());
  EXPECT_TRUE(accounts().check_session(again.token, kT0 + 10).ok());
}

TEST_P(AccountsTest, OnlyHashesAreStored) {
  register_ok("bob", "open sesame 123");
  const LoginResult login = must(accounts().login("bob", "open sesame 123", "", kT0), "login");
  const std::string hash = db_.query_one("SELECT password_hash FROM accounts");
  EXPECT_EQ(hash.rfind("$argon2id$", 0), 0u) << hash;
  EXPECT_EQ(hash.find("open sesame"), std::string::npos);
  const std::string token_hash = db_.query_one("SELECT token_hash FROM sessions");
  EXPECT_EQ(token_hash.size(), 32u);
  EXPECT_EQ(token_hash.find(login.token.substr(0, 16)), std::string::npos);
}

TEST_P(AccountsTest, DefaultCostIsArgon2idInteractive) {
  open(AccountsOptions{});
  register_ok("carol");
  const std::string hash = db_.query_one("SELECT password_hash FROM accounts");
  // libsodium's interactive limits: 64 MiB, 2 passes.
  EXPECT_EQ(hash.rfind("$argon2id$v=19$m=65536,t=2,p=1$", 0), 0u) << hash;
}

TEST_P(AccountsTest, LoginRehashesAPasswordMadeWithOtherLimits) {
  register_ok("dave");  // Minimum cost
  open(AccountsOptions{});
  ASSERT_TRUE(accounts().login("dave", "correct horse", "", kT0).ok());
  const std::string hash = db_.query_one("SELECT password_hash FROM accounts");
  EXPECT_EQ(hash.rfind("$argon2id$v=19$m=65536,t=2,p=1$", 0), 0u) << hash;
  EXPECT_TRUE(accounts().login("dave", "correct horse", "", kT0 + 1).ok());
}

TEST_P(AccountsTest, UsernameRules) {
  const std::vector<std::string> bad_names = {
      "",      "ab",    "abcdefghijklmnopqrstuvwxy", "a b",
      "name!", "émile", std::string("nul\0byte", 8), "semi;colon",
      "quote'"};
  for (const std::string& bad : bad_names) {
    EXPECT_TRUE(fails_with(accounts().register_account(bad, "correct horse", "", kT0),
                           DbErrorCode::InvalidUsername))
        << "'" << bad << "'";
  }
  for (const std::string good : {"abc", "abcdefghijklmnopqrstuvwx", "a_b-c.d", "ZZ9"}) {
    EXPECT_TRUE(accounts().register_account(good, "correct horse", "", kT0).ok()) << good;
  }
  EXPECT_EQ(errors(DbErrorCode::InvalidUsername), 9u);
}

TEST_P(AccountsTest, UsernamesAreUniqueIgnoringCase) {
  register_ok("Alice");
  EXPECT_TRUE(fails_with(accounts().register_account("alice", "correct horse", "", kT0),
                         DbErrorCode::DuplicateUsername));
  EXPECT_TRUE(fails_with(accounts().register_account("ALICE", "correct horse", "", kT0),
                         DbErrorCode::DuplicateUsername));
  EXPECT_TRUE(accounts().login("aLiCe", "correct horse", "", kT0).ok());
  EXPECT_EQ(errors(DbErrorCode::DuplicateUsername), 2u);
}

TEST_P(AccountsTest, PasswordRules) {
  EXPECT_TRUE(
      fails_with(accounts().register_account("erin", "", "", kT0), DbErrorCode::EmptyPassword));
  EXPECT_TRUE(fails_with(accounts().register_account("erin", "1234567", "", kT0),
                         DbErrorCode::PasswordTooShort));
  EXPECT_TRUE(fails_with(accounts().register_account("erin", std::string(1025, 'x'), "", kT0),
                         DbErrorCode::PasswordTooLong));
  EXPECT_TRUE(accounts().register_account("erin", "12345678", "", kT0).ok());
  EXPECT_TRUE(fails_with(accounts().login("erin", std::string(5000, 'x'), "", kT0),
                         DbErrorCode::PasswordTooLong));
}

TEST_P(AccountsTest, WrongPasswordAndUnknownNameLookTheSameAndCostTheSame) {
  register_ok("frank");
  const std::uint64_t checks = password_verifications();
  const auto wrong = accounts().login("frank", "wrong horse", "", kT0);
  const auto unknown = accounts().login("nobody", "wrong horse", "", kT0);
  const auto invalid = accounts().login("x", "wrong horse", "", kT0);
  for (const auto* r : {&wrong, &unknown, &invalid}) {
    ASSERT_TRUE(fails_with(*r, DbErrorCode::WrongCredentials));
    EXPECT_EQ(r->error().message, "wrong username or password");
  }
  // Each attempt ran exactly one Argon2id verification (a dummy one for unknown names).
  EXPECT_EQ(password_verifications() - checks, 3u);
}

TEST_P(AccountsTest, BannedAccountsCannotLogInAndLoseTheirSessions) {
  const AccountId id = register_ok("grace");
  const LoginResult login = must(accounts().login("grace", "correct horse", "", kT0), "login");
  RICOCHET_DB_ASSERT_OK(accounts().set_banned(id, true));
  EXPECT_TRUE(
      fails_with(accounts().check_session(login.token, kT0 + 1), DbErrorCode::UnknownSession));
  EXPECT_TRUE(fails_with(accounts().login("grace", "correct horse", "", kT0 + 2),
                         DbErrorCode::AccountBanned));
  // A wrong password on a banned account still says wrong credentials: the ban is only shown to
  // whoever knows the password.
  EXPECT_TRUE(fails_with(accounts().login("grace", "bad horse", "", kT0 + 2),
                         DbErrorCode::WrongCredentials));
  RICOCHET_DB_ASSERT_OK(accounts().set_banned(id, false));
  EXPECT_TRUE(accounts().login("grace", "correct horse", "", kT0 + 3).ok());
  EXPECT_TRUE(fails_with(accounts().set_banned(9999, true), DbErrorCode::UnknownAccount));
}

TEST_P(AccountsTest, AnAccountIsBannedByItsNameIgnoringCase) {
  const AccountId id = register_ok("Heidi");
  const LoginResult login = must(accounts().login("Heidi", "correct horse", "", kT0), "login");
  const Account banned = must(accounts().set_banned_by_name("hEIDI", true), "ban");
  EXPECT_EQ(banned.id, id);
  EXPECT_EQ(banned.username, "Heidi");
  EXPECT_TRUE(banned.banned);
  EXPECT_TRUE(
      fails_with(accounts().check_session(login.token, kT0 + 1), DbErrorCode::UnknownSession));
  EXPECT_TRUE(fails_with(accounts().login("Heidi", "correct horse", "", kT0 + 2),
                         DbErrorCode::AccountBanned));
  EXPECT_FALSE(must(accounts().set_banned_by_name("heidi", false), "unban").banned);
  EXPECT_TRUE(accounts().login("Heidi", "correct horse", "", kT0 + 3).ok());
  EXPECT_TRUE(
      fails_with(accounts().set_banned_by_name("nobody", true), DbErrorCode::UnknownAccount));
}

TEST_P(AccountsTest, SessionsExpire) {
  AccountsOptions o = fast_options();
  o.session_lifetime_ms = 1000;
  open(o);
  register_ok("heidi");
  const LoginResult login = must(accounts().login("heidi", "correct horse", "", kT0), "login");
  EXPECT_TRUE(accounts().check_session(login.token, kT0 + 999).ok());
  EXPECT_TRUE(
      fails_with(accounts().check_session(login.token, kT0 + 1000), DbErrorCode::ExpiredSession));
  // An expired session is removed once seen.
  EXPECT_TRUE(
      fails_with(accounts().check_session(login.token, kT0 + 1001), DbErrorCode::UnknownSession));
}

TEST_P(AccountsTest, RevokedAndMalformedTokensAreUnknown) {
  register_ok("ivan");
  const LoginResult login = must(accounts().login("ivan", "correct horse", "", kT0), "login");
  RICOCHET_DB_ASSERT_OK(accounts().revoke_session(login.token));
  EXPECT_TRUE(fails_with(accounts().check_session(login.token, kT0), DbErrorCode::UnknownSession));
  EXPECT_TRUE(fails_with(accounts().revoke_session(login.token), DbErrorCode::UnknownSession));
  std::string upper = login.token;
  for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  const std::vector<std::string> bad_tokens = {
      std::string(), "xyz", login.token.substr(1), upper, std::string(64, 'g'), login.token + "0"};
  for (const std::string& bad : bad_tokens) {
    EXPECT_TRUE(fails_with(accounts().check_session(bad, kT0), DbErrorCode::UnknownSession)) << bad;
  }
}

TEST_P(AccountsTest, ChangePassword) {
  const AccountId id = register_ok("judy");
  const LoginResult login = must(accounts().login("judy", "correct horse", "", kT0), "login");
  EXPECT_TRUE(fails_with(accounts().change_password(id, "wrong horse", "battery staple"),
                         DbErrorCode::WrongCredentials));
  EXPECT_TRUE(fails_with(accounts().change_password(id, "correct horse", "short"),
                         DbErrorCode::PasswordTooShort));
  EXPECT_TRUE(
      fails_with(accounts().change_password(id, "correct horse", ""), DbErrorCode::EmptyPassword));
  RICOCHET_DB_ASSERT_OK(accounts().change_password(id, "correct horse", "battery staple"));
  EXPECT_TRUE(fails_with(accounts().check_session(login.token, kT0), DbErrorCode::UnknownSession));
  EXPECT_TRUE(fails_with(accounts().login("judy", "correct horse", "", kT0),
                         DbErrorCode::WrongCredentials));
  EXPECT_TRUE(accounts().login("judy", "battery staple", "", kT0).ok());
  EXPECT_TRUE(fails_with(accounts().change_password(4242, "x", "battery staple"),
                         DbErrorCode::UnknownAccount));
}

// --- compound writes fail whole: the second write fails, and the first is undone ---

TEST_P(AccountsTest, APasswordChangeFailingHalfWayKeepsTheOldPasswordAndSessions) {
  const AccountId id = register_ok("kate");
  const LoginResult login = must(accounts().login("kate", "correct horse", "", kT0), "login");
  db_.inject_failure("BEFORE DELETE ON sessions");  // after the new hash is written
  EXPECT_TRUE(fails_with(accounts().change_password(id, "correct horse", "battery staple"),
                         DbErrorCode::Storage));
  EXPECT_TRUE(accounts().check_session(login.token, kT0 + 1).ok());
  db_.remove_failure();
  EXPECT_TRUE(accounts().login("kate", "correct horse", "", kT0 + 2).ok());
  EXPECT_TRUE(fails_with(accounts().login("kate", "battery staple", "", kT0 + 3),
                         DbErrorCode::WrongCredentials));
}

TEST_P(AccountsTest, ABanFailingHalfWayLeavesTheAccountAsItWas) {
  const AccountId id = register_ok("liam");
  const LoginResult login = must(accounts().login("liam", "correct horse", "", kT0), "login");
  db_.inject_failure("BEFORE DELETE ON sessions");  // after the banned flag is written
  EXPECT_TRUE(fails_with(accounts().set_banned(id, true), DbErrorCode::Storage));
  EXPECT_FALSE(must(store_->account(id), "account").banned);
  EXPECT_TRUE(accounts().check_session(login.token, kT0 + 1).ok());
}

TEST_P(AccountsTest, ALoginFailingHalfWayLeavesNoSessionAndNoUpgradedHash) {
  register_ok("mia");  // Minimum cost: the login below upgrades the hash first
  const std::string hash = db_.query_one("SELECT password_hash FROM accounts");
  open(AccountsOptions{});
  // The hash upgrade and the session are written; the login time is the write that fails.
  db_.inject_failure("BEFORE UPDATE OF last_login_ms ON accounts");
  EXPECT_TRUE(fails_with(accounts().login("mia", "correct horse", "", kT0), DbErrorCode::Storage));
  EXPECT_EQ(db_.query_one("SELECT COUNT(*) FROM sessions"), "0");
  EXPECT_EQ(db_.query_one("SELECT password_hash FROM accounts"), hash);
}

TEST_P(AccountsTest, FailedLoginsFromAllAddressesTogetherAreCappedPerAccount) {
  AccountsOptions o = fast_options();
  o.per_account = {3, 10'000};
  open(o);
  register_ok("mallory");
  for (int i = 0; i < 3; ++i) {
    const std::string address = "10.0.0." + std::to_string(i + 1);
    EXPECT_TRUE(fails_with(accounts().login("mallory", "guess", address, kT0 + i),
                           DbErrorCode::WrongCredentials));
  }
  const std::uint64_t checks = password_verifications();
  // Now even the right password is refused, from a fresh address too, and no hash is computed.
  EXPECT_TRUE(fails_with(accounts().login("MALLORY", "correct horse", "10.0.0.9", kT0 + 5),
                         DbErrorCode::RateLimited));
  EXPECT_EQ(password_verifications(), checks);
  // Once the oldest failure leaves the 10 s window, one more attempt is allowed.
  EXPECT_TRUE(accounts().login("mallory", "correct horse", "10.0.0.9", kT0 + 10'001).ok());
}

TEST_P(AccountsTest, AGuesserFromOneAddressDoesNotLockTheOwnerOut) {
  register_ok("victim");  // the default limits
  for (int i = 0; i < 5; ++i) {
    EXPECT_TRUE(fails_with(accounts().login("victim", "guess", "198.51.100.7", kT0 + i),
                           DbErrorCode::WrongCredentials));
  }
  const std::uint64_t checks = password_verifications();
  EXPECT_TRUE(fails_with(accounts().login("victim", "correct horse", "198.51.100.7", kT0 + 10),
                         DbErrorCode::RateLimited));
  EXPECT_EQ(password_verifications(), checks);
  // The owner, from its own address, at once; and from no address at all (a trusted caller).
  EXPECT_TRUE(accounts().login("victim", "correct horse", "203.0.113.5", kT0 + 11).ok());
  EXPECT_TRUE(accounts().login("victim", "correct horse", "", kT0 + 12).ok());
  // The owner's success does not forgive the guesser.
  EXPECT_TRUE(fails_with(accounts().login("victim", "guess", "198.51.100.7", kT0 + 13),
                         DbErrorCode::RateLimited));
}

TEST_P(AccountsTest, TheGuessersLimitBacksOff) {
  AccountsOptions o = fast_options();
  o.per_account_address = {{2, 1'000}, {4, 100'000}};
  open(o);
  register_ok("victim");
  const auto guess = [&](UnixMillis at) {
    return accounts().login("victim", "guess", "198.51.100.7", at);
  };
  EXPECT_TRUE(fails_with(guess(kT0), DbErrorCode::WrongCredentials));
  EXPECT_TRUE(fails_with(guess(kT0), DbErrorCode::WrongCredentials));
  EXPECT_TRUE(fails_with(guess(kT0 + 999), DbErrorCode::RateLimited));  // wait 1 s
  EXPECT_TRUE(fails_with(guess(kT0 + 1'000), DbErrorCode::WrongCredentials));
  EXPECT_TRUE(fails_with(guess(kT0 + 1'000), DbErrorCode::WrongCredentials));
  // Four failures: now the wait is the second step's, 100 s from the first failure.
  EXPECT_TRUE(fails_with(guess(kT0 + 2'000), DbErrorCode::RateLimited));
  EXPECT_TRUE(fails_with(guess(kT0 + 99'999), DbErrorCode::RateLimited));
  EXPECT_TRUE(fails_with(guess(kT0 + 100'000), DbErrorCode::WrongCredentials));
}

TEST_P(AccountsTest, TheOwnersSuccessForgetsItsOwnTyposOnly) {
  register_ok("owner");  // the default limits: 5 failures a minute per account and address
  for (int i = 0; i < 4; ++i) {
    EXPECT_TRUE(fails_with(accounts().login("owner", "typo", "203.0.113.5", kT0),
                           DbErrorCode::WrongCredentials));
  }
  for (int i = 0; i < 5; ++i) {
    EXPECT_TRUE(fails_with(accounts().login("owner", "guess", "198.51.100.7", kT0),
                           DbErrorCode::WrongCredentials));
  }
  EXPECT_TRUE(accounts().login("owner", "correct horse", "203.0.113.5", kT0 + 1).ok());
  // The owner's four typos are forgotten: five more before its address is limited.
  for (int i = 0; i < 5; ++i) {
    EXPECT_TRUE(fails_with(accounts().login("owner", "typo", "203.0.113.5", kT0 + 2),
                           DbErrorCode::WrongCredentials));
  }
  EXPECT_TRUE(fails_with(accounts().login("owner", "typo", "203.0.113.5", kT0 + 2),
                         DbErrorCode::RateLimited));
  // The guesser's are not.
  EXPECT_TRUE(fails_with(accounts().login("owner", "guess", "198.51.100.7", kT0 + 3),
                         DbErrorCode::RateLimited));
}

TEST_P(AccountsTest, RegistrationsPerAddressAreLimitedAcrossServerProcesses) {
  AccountsOptions o = fast_options();
  o.registrations_per_address = {2, 60'000};
  open(o);
  std::unique_ptr<Store> other_store = db_.open();
  Accounts other(*other_store, o);
  EXPECT_TRUE(accounts().register_account("bot1", "correct horse", "198.51.100.7", kT0).ok());
  // A taken name is refused before it counts (and before any hashing).
  EXPECT_TRUE(fails_with(other.register_account("BOT1", "correct horse", "198.51.100.7", kT0),
                         DbErrorCode::DuplicateUsername));
  EXPECT_TRUE(other.register_account("bot2", "correct horse", "198.51.100.7", kT0 + 1).ok());
  EXPECT_TRUE(
      fails_with(accounts().register_account("bot3", "correct horse", "198.51.100.7", kT0 + 2),
                 DbErrorCode::RateLimited));
  EXPECT_TRUE(fails_with(other.register_account("bot4", "correct horse", "198.51.100.7", kT0 + 3),
                         DbErrorCode::RateLimited));
  EXPECT_EQ(errors(DbErrorCode::RateLimited), 1u);
  // Another address registers; the limited one again once its window has passed.
  EXPECT_TRUE(accounts().register_account("ada", "correct horse", "203.0.113.5", kT0 + 4).ok());
  EXPECT_TRUE(
      accounts().register_account("bot3", "correct horse", "198.51.100.7", kT0 + 60'000).ok());
}

TEST_P(AccountsTest, ExpiredSessionsAreDeletedAsLoginsGoOn) {
  AccountsOptions o = fast_options();
  o.session_lifetime_ms = 1'000;
  open(o);
  register_ok("olga");
  const LoginResult first = must(accounts().login("olga", "correct horse", "", kT0), "login");
  const LoginResult second =
      must(accounts().login("olga", "correct horse", "", kT0 + 500), "login");
  ASSERT_TRUE(must(store_->find_session(token_hash(first.token)), "find").has_value());
  // A login after the first expired deletes it; the second is still live and kept.
  EXPECT_TRUE(accounts().login("olga", "correct horse", "", kT0 + 1'001).ok());
  EXPECT_FALSE(must(store_->find_session(token_hash(first.token)), "find").has_value());
  EXPECT_TRUE(must(store_->find_session(token_hash(second.token)), "find").has_value());
}

TEST_P(AccountsTest, FailedLoginsPerAddressAreRateLimited) {
  AccountsOptions o = fast_options();
  o.per_address = {4, 60'000};
  open(o);
  register_ok("oscar");
  for (int i = 0; i < 4; ++i) {
    EXPECT_TRUE(fails_with(accounts().login("user" + std::to_string(i), "guess", "10.1.1.1", kT0),
                           DbErrorCode::WrongCredentials));
  }
  EXPECT_TRUE(fails_with(accounts().login("oscar", "correct horse", "10.1.1.1", kT0 + 1),
                         DbErrorCode::RateLimited));
  EXPECT_TRUE(accounts().login("oscar", "correct horse", "10.2.2.2", kT0 + 1).ok());
  EXPECT_TRUE(accounts().login("oscar", "correct horse", "10.1.1.1", kT0 + 60'001).ok());
  EXPECT_EQ(errors(DbErrorCode::RateLimited), 1u);
  EXPECT_EQ(errors(DbErrorCode::WrongCredentials), 4u);
}

TEST_P(AccountsTest, ServerProcessesSharingADatabaseShareTheRateLimit) {
  AccountsOptions o = fast_options();
  o.per_account = {3, 10'000};
  o.per_address = {5, 10'000};
  o.per_account_address = {{5, 10'000}};
  o.registrations_per_address = {10, 10'000};
  open(o);
  register_ok("nina");
  // A second server process: its own store (connection) and Accounts on the same file.
  std::unique_ptr<Store> other_store = db_.open();
  Accounts other(*other_store, o);
  EXPECT_TRUE(fails_with(accounts().login("nina", "guess 1", "10.3.3.3", kT0),
                         DbErrorCode::WrongCredentials));
  EXPECT_TRUE(fails_with(other.login("nina", "guess 2", "10.3.3.3", kT0 + 1),
                         DbErrorCode::WrongCredentials));
  EXPECT_TRUE(fails_with(accounts().login("NINA", "guess 3", "10.4.4.4", kT0 + 2),
                         DbErrorCode::WrongCredentials));
  // Three failures between the two: both refuse the account now, even the right password.
  EXPECT_TRUE(fails_with(other.login("nina", "correct horse", "10.5.5.5", kT0 + 3),
                         DbErrorCode::RateLimited));
  EXPECT_TRUE(fails_with(accounts().login("nina", "correct horse", "10.5.5.5", kT0 + 3),
                         DbErrorCode::RateLimited));
  // The address limit is shared too: 10.3.3.3 has 2 failures noted, 3 more fill it.
  for (int i = 0; i < 3; ++i) {
    Accounts& either = i % 2 == 0 ? accounts() : other;
    EXPECT_TRUE(fails_with(either.login("user" + std::to_string(i), "guess", "10.3.3.3", kT0 + 4),
                           DbErrorCode::WrongCredentials));
  }
  EXPECT_TRUE(
      fails_with(other.login("someone", "guess", "10.3.3.3", kT0 + 5), DbErrorCode::RateLimited));
  // Both see the window pass, and the failures go on counting for both.
  EXPECT_TRUE(other.login("nina", "correct horse", "", kT0 + 10'001).ok());
  EXPECT_TRUE(fails_with(accounts().login("nina", "guess 4", "", kT0 + 10'002),
                         DbErrorCode::WrongCredentials));
  EXPECT_TRUE(accounts().login("nina", "correct horse", "", kT0 + 10'003).ok());
  // Failures older than both windows are dropped from the file as logins go on.
  EXPECT_EQ(db_.query_one("SELECT COUNT(*) FROM login_failures WHERE at_ms <= " +
                          std::to_string(kT0 + 3)),
            "0");
}

TEST_P(AccountsTest, EveryRefusalIsReportedForLoggingWithoutSecrets) {
  AccountsOptions o = fast_options();
  std::vector<DbError> refusals;
  o.on_refusal = [&](const DbError& e) { refusals.push_back(e); };
  open(o);
  register_ok("trent", "secret password 1");
  (void)accounts().register_account("trent", "secret password 2", "", kT0);
  (void)accounts().login("trent", "secret password 3", "10.9.9.9", kT0);
  (void)accounts().check_session(std::string(64, 'a'), kT0);
  ASSERT_EQ(refusals.size(), 3u);
  EXPECT_EQ(refusals[0].code, DbErrorCode::DuplicateUsername);
  EXPECT_EQ(refusals[1].code, DbErrorCode::WrongCredentials);
  EXPECT_EQ(refusals[2].code, DbErrorCode::UnknownSession);
  for (const DbError& e : refusals) {
    EXPECT_EQ(e.message.find("secret"), std::string::npos) << e.message;
    EXPECT_EQ(e.message.find(std::string(64, 'a')), std::string::npos) << e.message;
  }
}

TEST_P(AccountsTest, StateSurvivesReopening) {
  register_ok("peggy");
  const LoginResult login = must(accounts().login("peggy", "correct horse", "", kT0), "login");
  open(fast_options());
  EXPECT_TRUE(accounts().check_session(login.token, kT0 + 1).ok());
  EXPECT_TRUE(fails_with(accounts().register_account("Peggy", "correct horse", "", kT0),
                         DbErrorCode::DuplicateUsername));
}

INSTANTIATE_TEST_SUITE_P(Backends, AccountsTest, kBackends, backend_name);

}  // namespace
}  // namespace ricochet::db::test::accounts_test
