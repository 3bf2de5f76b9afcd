#pragma once
/// The two AEADs of the game channel, over libsodium (PROTOCOL.md Game channel transport §keys):
/// ChaCha20-Poly1305 IETF for packets and challenge tokens (12-byte nonce = 4 zero bytes + the
/// 64-bit sequence, little endian) and XChaCha20-Poly1305 IETF for connect tokens (24-byte
/// random nonce). Ciphertexts carry their 16-byte tag at the end.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "ricochet/proto/token_grant.h"

namespace ricochet::proto {

inline constexpr std::size_t kMacBytes = 16;     ///< Poly1305 tag
inline constexpr std::size_t kXNonceBytes = 24;  ///< XChaCha20 nonce
using XNonce = std::array<std::uint8_t, kXNonceBytes>;

/// Fills `out` from libsodium's CSPRNG.
void fill_random(std::span<std::uint8_t> out);
Key random_key();

/// Appends plaintext.size() + kMacBytes bytes to `out`.
void seal_chacha(std::span<const std::uint8_t> plaintext, std::span<const std::uint8_t> ad,
                 std::uint64_t nonce_sequence, const Key& key, std::vector<std::uint8_t>& out);
/// Encrypts `text` in place and writes its tag to `mac` (kMacBytes): what seal_chacha appends,
/// without a second buffer.
void seal_chacha_in_place(std::span<std::uint8_t> text, std::span<const std::uint8_t> ad,
                          std::uint64_t nonce_sequence, const Key& key, std::uint8_t* mac);
/// Replaces `out` with the plaintext; false (and `out` unspecified) when the tag does not verify
/// or the ciphertext is shorter than a tag.
bool open_chacha(std::span<const std::uint8_t> ciphertext, std::span<const std::uint8_t> ad,
                 std::uint64_t nonce_sequence, const Key& key, std::vector<std::uint8_t>& out);

void seal_xchacha(std::span<const std::uint8_t> plaintext, std::span<const std::uint8_t> ad,
                  const XNonce& nonce, const Key& key, std::vector<std::uint8_t>& out);
bool open_xchacha(std::span<const std::uint8_t> ciphertext, std::span<const std::uint8_t> ad,
                  const XNonce& nonce, const Key& key, std::vector<std::uint8_t>& out);

}  // namespace ricochet::proto
