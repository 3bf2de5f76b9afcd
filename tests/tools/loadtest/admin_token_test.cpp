#include "ricochet/loadtest/admin_token.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "ricochet/loadtest/loadtest_config.h"

namespace ricochet::loadtest::admin_token_test {
namespace {

namespace fs = std::filesystem;

TEST(AdminToken, TheTrailingNewlineAndSurroundingSpaceAreDroppedAsTheServerDoes) {
  std::string token;
  EXPECT_EQ(parse_admin_token("s3cret-token\n", token), "");
  EXPECT_EQ(token, "s3cret-token");
  EXPECT_EQ(parse_admin_token("  a b\r\n\n", token), "");
  EXPECT_EQ(token, "a b");
}

TEST(AdminToken, EmptyOrHeaderBreakingBytesAreRefusedNamingThem) {
  std::string token = "kept";
  EXPECT_EQ(parse_admin_token("", token), "is empty; write the servers' admin token into it");
  EXPECT_EQ(parse_admin_token(" \n\t", token), "is empty; write the servers' admin token into it");
  // A newline inside would end the Authorization header and start one of the file's choosing.
  EXPECT_EQ(parse_admin_token("abc\r\nX-Forged: 1", token),
            "has byte 13 at 3; a token is printable ASCII on one line");
  EXPECT_EQ(parse_admin_token(std::string("ab\0c", 4), token),
            "has byte 0 at 2; a token is printable ASCII on one line");
  EXPECT_EQ(parse_admin_token("caf\xc3\xa9", token),
            "has byte 195 at 3; a token is printable ASCII on one line");
  EXPECT_EQ(token, "kept");  // untouched by a refusal
}

TEST(AdminToken, AFileIsReadWithinItsBound) {
  const fs::path dir =
      fs::temp_directory_path() / ("ricochet-admin-token-" + std::to_string(getpid()));
  fs::create_directories(dir);
  std::string token;
  std::ofstream(dir / "ok") << "t0ken\n";
  EXPECT_EQ(read_admin_token((dir / "ok").string(), token), "");
  EXPECT_EQ(token, "t0ken");
  std::ofstream(dir / "large") << std::string(kMaxAdminTokenBytes + 1, 'x');
  EXPECT_EQ(read_admin_token((dir / "large").string(), token),
            "the admin token file " + (dir / "large").string() + " is larger than 4096 bytes");
  std::ofstream(dir / "empty") << "\n";
  EXPECT_NE(read_admin_token((dir / "empty").string(), token).find("is empty"), std::string::npos);
  EXPECT_EQ(read_admin_token((dir / "missing").string(), token),
            "cannot read the admin token file " + (dir / "missing").string());
  EXPECT_EQ(token, "t0ken");
  fs::remove_all(dir);
}

TEST(AdminToken, PerServerListsSplitOnCommas) {
  EXPECT_EQ(split_list(""), (std::vector<std::string>{}));
  EXPECT_EQ(split_list("a"), (std::vector<std::string>{"a"}));
  EXPECT_EQ(split_list("a,,b"), (std::vector<std::string>{"a", "", "b"}));
  EXPECT_EQ(split_list("a,"), (std::vector<std::string>{"a", ""}));
}

}  // namespace
}  // namespace ricochet::loadtest::admin_token_test
