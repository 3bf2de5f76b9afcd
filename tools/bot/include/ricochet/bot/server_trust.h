#pragma once
/// How a bot decides to trust the server's TLS certificate (PROTOCOL.md, The server certificate
/// and pinning): by its SHA-256 fingerprint, either pinned or trusted on first use into a file.
/// Chain validation is not used (the server's certificate is self-signed).

#include <openssl/x509.h>

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace ricochet::bot {

/// SHA-256 of the certificate's DER as 32 uppercase hex pairs joined by ':', as
/// `openssl x509 -noout -fingerprint -sha256` prints it and the server logs it.
std::string certificate_fingerprint_sha256(X509* certificate);

/// The fingerprint in the canonical form (uppercase, colons), or nullopt when `text` is not
/// 32 hex pairs (colons between pairs optional).
std::optional<std::string> normalize_fingerprint(std::string_view text);

class ServerTrust {
 public:
  /// Trusts exactly `fingerprint` (which must be canonical: see normalize_fingerprint);
  /// `source` names where it came from in a refusal.
  static ServerTrust pinned(std::string fingerprint, std::string source = "--fingerprint");
  /// Trusts what `file` holds; when it does not exist, the first fingerprint checked is
  /// written to it and trusted from then on.
  static ServerTrust on_first_use(std::filesystem::path file);

  /// Empty when a server presenting `fingerprint` is trusted; otherwise why not, with the fix.
  std::string check(const std::string& fingerprint);

 private:
  ServerTrust() = default;
  std::string trusted_;  ///< empty until known (first use)
  std::filesystem::path file_;
  std::string source_;  ///< of a pinned fingerprint
};

}  // namespace ricochet::bot
