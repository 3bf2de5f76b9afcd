#pragma once
/// The control channel's TLS identity: a certificate and its private key, loaded from the
/// configured paths or, when none are configured, from the data directory, where the first
/// start generates a self-signed pair (ECDSA P-256, SHA-256 signature, 10 years). Clients pin
/// the certificate by its SHA-256 fingerprint, which the server logs at start.

#include <filesystem>
#include <stdexcept>
#include <string>

namespace ricochet::server {

struct TlsIdentityPaths {
  /// Both set: load these (a missing file is an error). Both empty: use the data directory.
  std::filesystem::path certificate{};  ///< PEM; may hold a chain, leaf first
  std::filesystem::path private_key{};  ///< PEM, unencrypted
  /// Where the generated pair lives (control-cert.pem, control-key.pem); created if missing.
  std::filesystem::path data_dir{};
};

struct TlsIdentity {
  std::string certificate_pem;
  std::string private_key_pem;
  /// SHA-256 of the leaf certificate's DER bytes as 32 colon-separated uppercase hex pairs,
  /// as `openssl x509 -noout -fingerprint -sha256` prints it.
  std::string fingerprint_sha256;
  std::filesystem::path certificate_path;
  std::filesystem::path private_key_path;
  bool generated = false;  ///< made by this call (first start)
};

/// Why no identity could be had; the message names the file and what was wrong with it.
class TlsIdentityError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Loads the pair (checking that the key matches the certificate) or generates one, as above.
/// Throws TlsIdentityError.
TlsIdentity load_or_create_tls_identity(const TlsIdentityPaths& paths);

/// The fingerprint (format above) of the first certificate in `certificate_pem`. Throws
/// TlsIdentityError when it holds none.
std::string certificate_fingerprint_sha256(const std::string& certificate_pem);

}  // namespace ricochet::server
