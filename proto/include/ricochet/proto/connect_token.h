#pragma once
/// Connect tokens (PROTOCOL.md Game channel transport §connect token): made by the server when the
/// control channel admits a player to a match, handed to the client over TLS, and sent back as is
/// in the connection request. Sealed with XChaCha20-Poly1305 under a key only the server knows, so
/// a client can neither read nor forge one.
///
///   token (128 bytes) = 24-byte random nonce | XChaCha20-Poly1305(plaintext) incl. 16-byte tag
///   plaintext (88 bytes) = u64 account_id | u32 match_id | i64 expires_at_us | u32 timeout_s
///                          | 32 client_to_server key | 32 server_to_client key
///   additional data = 16-byte version | u64 protocol_id
/// The tag (the token's last 16 bytes) names the token: the server remembers it to allow each
/// token from one client address only.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "ricochet/proto/clock.h"
#include "ricochet/proto/crypto.h"
#include "ricochet/proto/packet.h"
#include "ricochet/proto/token_grant.h"

namespace ricochet::proto {

inline constexpr std::size_t kConnectTokenPlainBytes = 8 + 4 + 8 + 4 + 2 * kKeyBytes;
inline constexpr std::size_t kConnectTokenBytes =
    kXNonceBytes + kConnectTokenPlainBytes + kMacBytes;
inline constexpr TimeUs kMaxTokenLifetimeUs = 30 * kMicrosPerSecond;
inline constexpr std::uint32_t kMinTimeoutS = 1;
inline constexpr std::uint32_t kMaxTimeoutS = 60;
using TokenMac = std::array<std::uint8_t, kMacBytes>;

struct ConnectTokenContents {
  std::uint64_t account_id = 0;
  std::uint32_t match_id = 0;
  TimeUs expires_at = 0;        ///< on the issuing server's clock
  std::uint32_t timeout_s = 0;  ///< kMinTimeoutS..kMaxTimeoutS
  Key client_to_server{};
  Key server_to_client{};
  friend bool operator==(const ConnectTokenContents&, const ConnectTokenContents&) = default;
};

/// Called by the control channel on join. `token_key` is the server-only key; the two session
/// keys are fresh. Throws std::invalid_argument when lifetime_us is not in (0, 30 s] or
/// timeout_s not in [1, 60] (a caller's bug, not untrusted input).
TokenGrant issue_connect_token(const Key& token_key, std::uint64_t protocol_id,
                               std::uint64_t account_id, std::uint32_t match_id, TimeUs now,
                               TimeUs lifetime_us, std::uint32_t timeout_s);

/// The sealed plaintext's codec, apart so that it can be fuzzed without the key.
std::vector<std::uint8_t> encode_connect_token_plaintext(const ConnectTokenContents& contents);
/// Refuses (Malformed) a wrong length or a timeout outside [1, 60].
Parsed<ConnectTokenContents> decode_connect_token_plaintext(std::span<const std::uint8_t> plain);

struct OpenedConnectToken {
  ConnectTokenContents contents;
  TokenMac mac{};
};
/// Opens a token from a connection request: Malformed (wrong length), TokenInvalid (does not
/// open under token_key for protocol_id, or bad contents), TokenExpired (now >= expires_at, or
/// an expiry further than 30 s ahead, which this server never issues).
Parsed<OpenedConnectToken> open_connect_token(const Key& token_key, std::uint64_t protocol_id,
                                              std::span<const std::uint8_t> token, TimeUs now);

}  // namespace ricochet::proto
