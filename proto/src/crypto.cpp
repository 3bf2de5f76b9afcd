#include "ricochet/proto/crypto.h"

#include <sodium.h>

#include <cstdio>
#include <cstdlib>

namespace ricochet::proto {
namespace {

/// sodium_init is idempotent and thread-safe; it picks the fastest implementations.
void ensure_sodium() {
  static const bool ready = [] {
    if (sodium_init() < 0) {
      std::fputs("libsodium failed to initialise (sodium_init < 0)\n", stderr);
      std::abort();
    }
    return true;
  }();
  (void)ready;
}

std::array<std::uint8_t, crypto_aead_chacha20poly1305_IETF_NPUBBYTES> packet_nonce(
    std::uint64_t sequence) {
  std::array<std::uint8_t, crypto_aead_chacha20poly1305_IETF_NPUBBYTES> nonce{};
  for (int i = 0; i < 8; ++i) nonce[4 + i] = static_cast<std::uint8_t>(sequence >> (8 * i));
  return nonce;
}

}  // namespace

static_assert(kMacBytes == crypto_aead_chacha20poly1305_IETF_ABYTES);
static_assert(kMacBytes == crypto_aead_xchacha20poly1305_IETF_ABYTES);
static_assert(kXNonceBytes == crypto_aead_xchacha20poly1305_IETF_NPUBBYTES);
static_assert(kKeyBytes == crypto_aead_chacha20poly1305_IETF_KEYBYTES);

void fill_random(std::span<std::uint8_t> out) {
  ensure_sodium();
  randombytes_buf(out.data(), out.size());
}

Key random_key() {
  Key key;
  fill_random(key);
  return key;
}

void seal_chacha(std::span<const std::uint8_t> plaintext, std::span<const std::uint8_t> ad,
                 std::uint64_t nonce_sequence, const Key& key, std::vector<std::uint8_t>& out) {
  ensure_sodium();
  const std::size_t start = out.size();
  out.resize(start + plaintext.size() + kMacBytes);
  unsigned long long written = 0;
  const auto nonce = packet_nonce(nonce_sequence);
  crypto_aead_chacha20poly1305_ietf_encrypt(out.data() + start, &written, plaintext.data(),
                                            plaintext.size(), ad.data(), ad.size(), nullptr,
                                            nonce.data(), key.data());
}

void seal_chacha_in_place(std::span<std::uint8_t> text, std::span<const std::uint8_t> ad,
                          std::uint64_t nonce_sequence, const Key& key, std::uint8_t* mac) {
  ensure_sodium();
  const auto nonce = packet_nonce(nonce_sequence);
  // libsodium XORs the key stream over the message and authenticates the ciphertext, so the
  // message may be the ciphertext's own buffer.
  crypto_aead_chacha20poly1305_ietf_encrypt_detached(text.data(), mac, nullptr, text.data(),
                                                     text.size(), ad.data(), ad.size(), nullptr,
                                                     nonce.data(), key.data());
}

bool open_chacha(std::span<const std::uint8_t> ciphertext, std::span<const std::uint8_t> ad,
                 std::uint64_t nonce_sequence, const Key& key, std::vector<std::uint8_t>& out) {
  ensure_sodium();
  if (ciphertext.size() < kMacBytes) return false;
  out.resize(ciphertext.size() - kMacBytes + 1);  // +1: never a null pointer for empty bodies
  unsigned long long written = 0;
  const auto nonce = packet_nonce(nonce_sequence);
  if (crypto_aead_chacha20poly1305_ietf_decrypt(out.data(), &written, nullptr, ciphertext.data(),
                                                ciphertext.size(), ad.data(), ad.size(),
                                                nonce.data(), key.data()) != 0) {
    return false;
  }
  out.resize(written);
  return true;
}

void seal_xchacha(std::span<const std::uint8_t> plaintext, std::span<const std::uint8_t> ad,
                  const XNonce& nonce, const Key& key, std::vector<std::uint8_t>& out) {
  ensure_sodium();
  const std::size_t start = out.size();
  out.resize(start + plaintext.size() + kMacBytes);
  unsigned long long written = 0;
  crypto_aead_xchacha20poly1305_ietf_encrypt(out.data() + start, &written, plaintext.data(),
                                             plaintext.size(), ad.data(), ad.size(), nullptr,
                                             nonce.data(), key.data());
}

bool open_xchacha(std::span<const std::uint8_t> ciphertext, std::span<const std::uint8_t> ad,
                  const XNonce& nonce, const Key& key, std::vector<std::uint8_t>& out) {
  ensure_sodium();
  if (ciphertext.size() < kMacBytes) return false;
  out.resize(ciphertext.size() - kMacBytes + 1);
  unsigned long long written = 0;
  if (crypto_aead_xchacha20poly1305_ietf_decrypt(out.data(), &written, nullptr, ciphertext.data(),
                                                 ciphertext.size(), ad.data(), ad.size(),
                                                 nonce.data(), key.data()) != 0) {
    return false;
  }
  out.resize(written);
  return true;
}

}  // namespace ricochet::proto
