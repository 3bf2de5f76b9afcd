// The control channel's TLS identity: generated once into the data directory (key readable by
// the owner only) and loaded again with the same fingerprint; configured paths are loaded and
// checked; every bad combination is an error that names the file.

#include "tls_identity.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <fstream>
#include <regex>

#include "control_test_client.h"

namespace ricochet::server::test::tls_identity_test {
namespace {

std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(TlsIdentity, GeneratedOnceThenLoadedWithTheSameFingerprint) {
  TempDir dir;
  const TlsIdentityPaths paths{.data_dir = dir.path() / "data"};
  const TlsIdentity first = load_or_create_tls_identity(paths);
  EXPECT_TRUE(first.generated);
  EXPECT_TRUE(
      std::regex_match(first.fingerprint_sha256, std::regex("([0-9A-F]{2}:){31}[0-9A-F]{2}")))
      << first.fingerprint_sha256;
  EXPECT_EQ(first.certificate_path, dir.path() / "data" / "control-cert.pem");
  EXPECT_EQ(slurp(first.certificate_path), first.certificate_pem);

  struct stat key_stat {};
  ASSERT_EQ(::stat(first.private_key_path.c_str(), &key_stat), 0);
  EXPECT_EQ(key_stat.st_mode & 0777, 0600u);

  const TlsIdentity second = load_or_create_tls_identity(paths);
  EXPECT_FALSE(second.generated);
  EXPECT_EQ(second.fingerprint_sha256, first.fingerprint_sha256);
  EXPECT_EQ(certificate_fingerprint_sha256(second.certificate_pem), first.fingerprint_sha256);
}

TEST(TlsIdentity, TheKeyIsWrittenToANewPrivateFileInAPrivateDirectory) {
  TempDir dir;
  const std::filesystem::path data = dir.path() / "data";
  std::filesystem::create_directories(data);
  // A key.pem.tmp left world-readable, and a link planted where the certificate's temporary
  // goes, pointing at a file of the attacker's.
  const std::filesystem::path stale = data / "control-key.pem.tmp";
  std::ofstream(stale) << "stale";
  std::filesystem::permissions(stale, std::filesystem::perms::all);
  const std::filesystem::path elsewhere = dir.path() / "attacker-readable";
  std::ofstream(elsewhere) << "untouched";
  std::filesystem::create_symlink(elsewhere, data / "control-cert.pem.tmp");

  const TlsIdentity made = load_or_create_tls_identity({.data_dir = data});
  struct stat key_stat {};
  ASSERT_EQ(::lstat(made.private_key_path.c_str(), &key_stat), 0);
  EXPECT_TRUE(S_ISREG(key_stat.st_mode));
  EXPECT_EQ(key_stat.st_mode & 0777, 0600u);
  EXPECT_EQ(slurp(elsewhere), "untouched");  // not written through the link
  struct stat certificate_stat {};
  ASSERT_EQ(::lstat(made.certificate_path.c_str(), &certificate_stat), 0);
  EXPECT_TRUE(S_ISREG(certificate_stat.st_mode));

  // A data directory the identity makes itself is the owner's alone.
  const std::filesystem::path fresh = dir.path() / "fresh" / "data";
  load_or_create_tls_identity({.data_dir = fresh});
  struct stat dir_stat {};
  ASSERT_EQ(::stat(fresh.c_str(), &dir_stat), 0);
  EXPECT_EQ(dir_stat.st_mode & 0777, 0700u);
}

TEST(TlsIdentity, ConfiguredPathsAreLoaded) {
  TempDir dir;
  const TlsIdentity generated = load_or_create_tls_identity({.data_dir = dir.path()});
  const TlsIdentity loaded = load_or_create_tls_identity(
      {.certificate = generated.certificate_path, .private_key = generated.private_key_path});
  EXPECT_FALSE(loaded.generated);
  EXPECT_EQ(loaded.fingerprint_sha256, generated.fingerprint_sha256);
}

TEST(TlsIdentity, KeyOfAnotherCertificateIsRefused) {
  TempDir one;
  TempDir two;
  const TlsIdentity a = load_or_create_tls_identity({.data_dir = one.path()});
  const TlsIdentity b = load_or_create_tls_identity({.data_dir = two.path()});
  EXPECT_NE(a.fingerprint_sha256, b.fingerprint_sha256);
  try {
    load_or_create_tls_identity(
        {.certificate = a.certificate_path, .private_key = b.private_key_path});
    FAIL() << "a mismatched pair was accepted";
  } catch (const TlsIdentityError& error) {
    EXPECT_NE(std::string(error.what()).find("is not the key of the certificate"),
              std::string::npos)
        << error.what();
  }
}

TEST(TlsIdentity, BadConfigurationsAreErrors) {
  TempDir dir;
  EXPECT_THROW(load_or_create_tls_identity({.certificate = dir.path() / "cert.pem"}),
               TlsIdentityError);                                   // a key path is missing
  EXPECT_THROW(load_or_create_tls_identity({}), TlsIdentityError);  // nowhere to generate
  EXPECT_THROW(load_or_create_tls_identity({.certificate = dir.path() / "missing.pem",
                                            .private_key = dir.path() / "missing-key.pem"}),
               TlsIdentityError);
  // Only half of a generated pair: refused rather than silently replaced.
  const TlsIdentity generated = load_or_create_tls_identity({.data_dir = dir.path()});
  std::filesystem::remove(generated.private_key_path);
  EXPECT_THROW(load_or_create_tls_identity({.data_dir = dir.path()}), TlsIdentityError);
  // A file that is not PEM.
  std::ofstream(dir.path() / "garbage.pem") << "not a certificate";
  EXPECT_THROW(load_or_create_tls_identity({.certificate = dir.path() / "garbage.pem",
                                            .private_key = dir.path() / "garbage.pem"}),
               TlsIdentityError);
}

TEST(TlsIdentity, ServerConfigIsValidated) {
  ControlServerConfig config;
  EXPECT_EQ(config.validate(), "");
  config.bind_address = "localhost:7777";
  EXPECT_NE(config.validate().find("bind_address"), std::string::npos);
  config.bind_address = "::1";
  config.limits.max_connections_per_address = config.limits.max_connections + 1;
  EXPECT_NE(config.validate().find("max_connections_per_address"), std::string::npos);
  config.limits = {};
  config.limits.frame_timeout_ms = 0;
  EXPECT_EQ(config.validate(), "control.frame_timeout_ms must be 10..3600000, got 0");
}

}  // namespace
}  // namespace ricochet::server::test::tls_identity_test
