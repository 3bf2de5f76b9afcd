#include "tls_identity.h"

#include <fcntl.h>
#include <openssl/bio.h>
#include <openssl/err.h>
#include <openssl/evp.h>
#include <openssl/pem.h>
#include <openssl/rand.h>
#include <openssl/x509.h>
#include <openssl/x509v3.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <system_error>

namespace ricochet::server {
namespace {

constexpr const char* kGeneratedCertificate = "control-cert.pem";
constexpr const char* kGeneratedKey = "control-key.pem";
constexpr long kValiditySeconds = 10L * 365 * 24 * 3600;

struct BioFree {
  void operator()(BIO* bio) const { BIO_free(bio); }
};
struct X509Free {
  void operator()(X509* x509) const { X509_free(x509); }
};
struct KeyFree {
  void operator()(EVP_PKEY* key) const { EVP_PKEY_free(key); }
};
using Bio = std::unique_ptr<BIO, BioFree>;
using Certificate = std::unique_ptr<X509, X509Free>;
using PrivateKey = std::unique_ptr<EVP_PKEY, KeyFree>;

/// The oldest queued OpenSSL error as text, and the queue cleared.
std::string openssl_error() {
  const unsigned long code = ERR_get_error();
  ERR_clear_error();
  if (code == 0) return "no OpenSSL error queued";
  std::array<char, 256> text{};
  ERR_error_string_n(code, text.data(), text.size());
  return text.data();
}

[[noreturn]] void fail(const std::string& what) {
  throw TlsIdentityError(what + " (" + openssl_error() + ")");
}

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw TlsIdentityError("cannot read " + path.string() + ": " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Writes `text` to `path` through a temporary file and a rename, readable by the owner only
/// when `secret`. The temporary is a new file (O_EXCL, O_NOFOLLOW; one left by a crash, or a
/// link planted there, is removed first, never written through), given its mode explicitly.
void write_file(const std::filesystem::path& path, const std::string& text, bool secret) {
  const std::filesystem::path temporary = path.string() + ".tmp";
  const mode_t mode = secret ? 0600 : 0644;
  if (::unlink(temporary.c_str()) != 0 && errno != ENOENT) {
    throw TlsIdentityError("cannot remove the leftover " + temporary.string() + ": " +
                           std::strerror(errno));
  }
  const int fd =
      ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, mode);
  if (fd < 0) {
    throw TlsIdentityError("cannot create " + temporary.string() + ": " + std::strerror(errno));
  }
  if (::fchmod(fd, mode) != 0) {
    const int error = errno;
    ::close(fd);
    throw TlsIdentityError("cannot set the mode of " + temporary.string() + ": " +
                           std::strerror(error));
  }
  std::size_t written = 0;
  while (written < text.size()) {
    const ssize_t n = ::write(fd, text.data() + written, text.size() - written);
    if (n < 0) {
      const int error = errno;
      ::close(fd);
      throw TlsIdentityError("cannot write " + temporary.string() + ": " + std::strerror(error));
    }
    written += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    throw TlsIdentityError("cannot flush " + temporary.string() + ": " + std::strerror(errno));
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) throw TlsIdentityError("cannot rename to " + path.string() + ": " + error.message());
}

Bio memory_bio(const std::string& text) {
  Bio bio(BIO_new_mem_buf(text.data(), static_cast<int>(text.size())));
  if (!bio) fail("cannot allocate a memory BIO");
  return bio;
}

std::string bio_text(BIO* bio) {
  char* data = nullptr;
  const long size = BIO_get_mem_data(bio, &data);
  return std::string(data, static_cast<std::size_t>(size));
}

Certificate parse_certificate(const std::string& pem, const std::string& origin) {
  Bio bio = memory_bio(pem);
  Certificate certificate(PEM_read_bio_X509(bio.get(), nullptr, nullptr, nullptr));
  if (!certificate) fail(origin + " holds no PEM certificate");
  return certificate;
}

PrivateKey parse_key(const std::string& pem, const std::string& origin) {
  Bio bio = memory_bio(pem);
  PrivateKey key(PEM_read_bio_PrivateKey(bio.get(), nullptr, nullptr, nullptr));
  if (!key) fail(origin + " holds no unencrypted PEM private key");
  return key;
}

std::string fingerprint(X509* certificate) {
  std::array<unsigned char, EVP_MAX_MD_SIZE> digest{};
  unsigned int size = 0;
  if (X509_digest(certificate, EVP_sha256(), digest.data(), &size) != 1) {
    fail("cannot hash the certificate");
  }
  std::string text;
  for (unsigned int i = 0; i < size; ++i) {
    std::array<char, 4> pair{};
    std::snprintf(pair.data(), pair.size(), "%02X", digest[i]);
    if (i > 0) text += ':';
    text += pair.data();
  }
  return text;
}

void add_extension(X509* certificate, int nid, const char* value) {
  X509V3_CTX context;
  X509V3_set_ctx_nodb(&context);
  X509V3_set_ctx(&context, certificate, certificate, nullptr, nullptr, 0);
  X509_EXTENSION* extension = X509V3_EXT_conf_nid(nullptr, &context, nid, value);
  if (!extension) fail(std::string("cannot make the extension ") + value);
  const int added = X509_add_ext(certificate, extension, -1);
  X509_EXTENSION_free(extension);
  if (added != 1) fail(std::string("cannot add the extension ") + value);
}

/// A fresh P-256 key and a self-signed certificate for it, both as PEM.
std::pair<std::string, std::string> generate_pair() {
  PrivateKey key(EVP_EC_gen("P-256"));
  if (!key) fail("cannot generate a P-256 key");
  Certificate certificate(X509_new());
  if (!certificate) fail("cannot allocate a certificate");
  X509_set_version(certificate.get(), X509_VERSION_3);
  std::array<unsigned char, 16> serial{};
  if (RAND_bytes(serial.data(), static_cast<int>(serial.size())) != 1) fail("no random serial");
  serial[0] &= 0x7f;  // a positive INTEGER
  BIGNUM* number = BN_bin2bn(serial.data(), static_cast<int>(serial.size()), nullptr);
  const bool serial_set =
      number && BN_to_ASN1_INTEGER(number, X509_get_serialNumber(certificate.get())) != nullptr;
  BN_free(number);
  if (!serial_set) fail("cannot set the serial number");
  if (!X509_gmtime_adj(X509_getm_notBefore(certificate.get()), -3600) ||
      !X509_gmtime_adj(X509_getm_notAfter(certificate.get()), kValiditySeconds)) {
    fail("cannot set the validity");
  }
  X509_NAME* subject = X509_get_subject_name(certificate.get());
  const auto* common_name = reinterpret_cast<const unsigned char*>("ricochet-server");
  if (X509_NAME_add_entry_by_txt(subject, "CN", MBSTRING_ASC, common_name, -1, -1, 0) != 1 ||
      X509_set_issuer_name(certificate.get(), subject) != 1 ||
      X509_set_pubkey(certificate.get(), key.get()) != 1) {
    fail("cannot fill the certificate");
  }
  add_extension(certificate.get(), NID_basic_constraints, "critical,CA:FALSE");
  add_extension(certificate.get(), NID_key_usage, "critical,digitalSignature");
  add_extension(certificate.get(), NID_ext_key_usage, "serverAuth");
  add_extension(certificate.get(), NID_subject_alt_name, "DNS:localhost,IP:127.0.0.1,IP:::1");
  if (X509_sign(certificate.get(), key.get(), EVP_sha256()) == 0) fail("cannot sign");

  Bio certificate_out(BIO_new(BIO_s_mem()));
  Bio key_out(BIO_new(BIO_s_mem()));
  if (!certificate_out || !key_out ||
      PEM_write_bio_X509(certificate_out.get(), certificate.get()) != 1 ||
      PEM_write_bio_PrivateKey(key_out.get(), key.get(), nullptr, nullptr, 0, nullptr, nullptr) !=
          1) {
    fail("cannot write the pair as PEM");
  }
  return {bio_text(certificate_out.get()), bio_text(key_out.get())};
}

/// Reads and checks a pair: both parse, and the key is the certificate's.
TlsIdentity load_pair(const std::filesystem::path& certificate_path,
                      const std::filesystem::path& key_path) {
  TlsIdentity identity;
  identity.certificate_path = certificate_path;
  identity.private_key_path = key_path;
  identity.certificate_pem = read_file(certificate_path);
  identity.private_key_pem = read_file(key_path);
  const Certificate certificate =
      parse_certificate(identity.certificate_pem, certificate_path.string());
  const PrivateKey key = parse_key(identity.private_key_pem, key_path.string());
  if (X509_check_private_key(certificate.get(), key.get()) != 1) {
    fail("the key in " + key_path.string() + " is not the key of the certificate in " +
         certificate_path.string());
  }
  identity.fingerprint_sha256 = fingerprint(certificate.get());
  return identity;
}

}  // namespace

std::string certificate_fingerprint_sha256(const std::string& certificate_pem) {
  return fingerprint(parse_certificate(certificate_pem, "the PEM text").get());
}

TlsIdentity load_or_create_tls_identity(const TlsIdentityPaths& paths) {
  if (paths.certificate.empty() != paths.private_key.empty()) {
    throw TlsIdentityError(
        "set both the TLS certificate and key paths or neither; got certificate '" +
        paths.certificate.string() + "' and key '" + paths.private_key.string() + "'");
  }
  if (!paths.certificate.empty()) return load_pair(paths.certificate, paths.private_key);
  if (paths.data_dir.empty()) {
    throw TlsIdentityError(
        "no TLS certificate and key configured and no data directory to "
        "generate them in");
  }
  const std::filesystem::path certificate_path = paths.data_dir / kGeneratedCertificate;
  const std::filesystem::path key_path = paths.data_dir / kGeneratedKey;
  const bool have_certificate = std::filesystem::exists(certificate_path);
  const bool have_key = std::filesystem::exists(key_path);
  if (have_certificate && have_key) return load_pair(certificate_path, key_path);
  if (have_certificate != have_key) {
    throw TlsIdentityError("found only one of " + certificate_path.string() + " and " +
                           key_path.string() + "; remove it to generate a new pair");
  }
  std::error_code error;
  // A directory made here holds the key: the owner's alone (0700).
  if (std::filesystem::create_directories(paths.data_dir, error)) {
    std::filesystem::permissions(paths.data_dir, std::filesystem::perms::owner_all,
                                 std::filesystem::perm_options::replace, error);
  }
  if (error) {
    throw TlsIdentityError("cannot create the data directory " + paths.data_dir.string() +
                           " (mode 0700): " + error.message());
  }
  auto [certificate_pem, key_pem] = generate_pair();
  write_file(key_path, key_pem, true);
  write_file(certificate_path, certificate_pem, false);
  TlsIdentity identity = load_pair(certificate_path, key_path);
  identity.generated = true;
  return identity;
}

}  // namespace ricochet::server
