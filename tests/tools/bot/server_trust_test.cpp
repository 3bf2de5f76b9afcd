#include "ricochet/bot/server_trust.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "temp_dir.h"

namespace ricochet::bot::server_trust_test {
namespace {

std::string fingerprint_of(const std::string& pair) {
  std::string text;
  for (int i = 0; i < 32; ++i) {
    if (i) text += ':';
    text += pair;
  }
  return text;
}

TEST(ServerTrust, NormalizesOnlyThirtyTwoHexPairs) {
  EXPECT_EQ(normalize_fingerprint(fingerprint_of("ab")), fingerprint_of("AB"));
  EXPECT_EQ(normalize_fingerprint(std::string(64, 'c')), fingerprint_of("CC"));
  EXPECT_FALSE(normalize_fingerprint(""));
  EXPECT_FALSE(normalize_fingerprint(fingerprint_of("AB").substr(3)));  // 31 pairs
  EXPECT_FALSE(normalize_fingerprint(fingerprint_of("AB") + ":AB"));    // 33 pairs
  EXPECT_FALSE(normalize_fingerprint(fingerprint_of("AG")));
  std::string leading_colon = ":";
  leading_colon += fingerprint_of("AB");
  EXPECT_FALSE(normalize_fingerprint(leading_colon));
  std::string odd_digit = "A";
  odd_digit += fingerprint_of("AB");
  EXPECT_FALSE(normalize_fingerprint(odd_digit));
}

TEST(ServerTrust, PinnedTrustsOnlyItsFingerprint) {
  ServerTrust trust = ServerTrust::pinned(fingerprint_of("AB"));
  EXPECT_EQ(trust.check(fingerprint_of("AB")), "");
  const std::string refusal = trust.check(fingerprint_of("CD"));
  EXPECT_NE(refusal.find("is not the trusted"), std::string::npos) << refusal;
  EXPECT_NE(refusal.find("--fingerprint"), std::string::npos) << refusal;
  EXPECT_NE(trust.check(""), "");
}

TEST(ServerTrust, APinFromAnAssignmentSaysWhereItCameFromWhenItRefuses) {
  ServerTrust trust =
      ServerTrust::pinned(fingerprint_of("AB"), "the assignment from 127.0.0.1:7777");
  EXPECT_EQ(trust.check(fingerprint_of("AB")), "");
  const std::string refusal = trust.check(fingerprint_of("CD"));
  EXPECT_NE(refusal.find("(from the assignment from 127.0.0.1:7777)"), std::string::npos)
      << refusal;
  EXPECT_EQ(refusal.find("--fingerprint"), std::string::npos) << refusal;
}

TEST(ServerTrust, FirstUseWritesTheFileAndRefusesAnotherFingerprintLater) {
  ricochet::test::TempDir dir("ricochet-trust");
  const auto file = dir.path() / "trusted";
  ServerTrust first = ServerTrust::on_first_use(file);
  EXPECT_EQ(first.check(fingerprint_of("AB")), "");
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, fingerprint_of("AB"));
  EXPECT_EQ(first.check(fingerprint_of("AB")), "");
  EXPECT_NE(first.check(fingerprint_of("CD")), "");

  // Another process (or a later run) reads the same file.
  ServerTrust later = ServerTrust::on_first_use(file);
  EXPECT_EQ(later.check(fingerprint_of("AB")), "");
  ServerTrust changed = ServerTrust::on_first_use(file);
  const std::string refusal = changed.check(fingerprint_of("CD"));
  EXPECT_NE(refusal.find(file.string()), std::string::npos) << refusal;
}

TEST(ServerTrust, AFileThatHoldsNoFingerprintIsRefused) {
  ricochet::test::TempDir dir("ricochet-trust");
  const auto file = dir.path() / "trusted";
  std::ofstream(file) << "not a fingerprint\n";
  ServerTrust trust = ServerTrust::on_first_use(file);
  EXPECT_NE(trust.check(fingerprint_of("AB")).find("fix or delete it"), std::string::npos);
}

}  // namespace
}  // namespace ricochet::bot::server_trust_test
