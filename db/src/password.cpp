/// libsodium wrappers (password.h). sodium_init() runs once, before the first use.

#include "password.h"

#include <sodium.h>

#include <array>
#include <atomic>
#include <stdexcept>
#include <vector>

namespace ricochet::db {

namespace {

void ensure_sodium() {
  static const bool ready = sodium_init() >= 0;
  if (!ready) throw std::runtime_error("libsodium failed to initialise");
}

struct Limits {
  unsigned long long ops;
  std::size_t memory;  ///< bytes
};

Limits limits_of(PasswordCost cost) {
  switch (cost) {
    case PasswordCost::Interactive:
      return {crypto_pwhash_OPSLIMIT_INTERACTIVE, crypto_pwhash_MEMLIMIT_INTERACTIVE};
    case PasswordCost::Moderate:
      return {crypto_pwhash_OPSLIMIT_MODERATE, crypto_pwhash_MEMLIMIT_MODERATE};
    case PasswordCost::Minimum:
      return {crypto_pwhash_OPSLIMIT_MIN, crypto_pwhash_MEMLIMIT_MIN};
  }
  return {crypto_pwhash_OPSLIMIT_INTERACTIVE, crypto_pwhash_MEMLIMIT_INTERACTIVE};
}

std::atomic<std::uint64_t> g_verifications{0};

}  // namespace

DbResult<std::string> hash_password(std::string_view password, PasswordCost cost) {
  ensure_sodium();
  const Limits limits = limits_of(cost);
  std::array<char, crypto_pwhash_STRBYTES> out{};
  if (crypto_pwhash_str_alg(out.data(), password.data(), password.size(), limits.ops, limits.memory,
                            crypto_pwhash_ALG_ARGON2ID13) != 0) {
    return DbError{
        DbErrorCode::OutOfMemory,
        "hashing a password could not allocate the " + std::to_string(limits.memory / 1024) +
            " KiB Argon2id needs; lower DbWorkerOptions::password_threads or free memory"};
  }
  return std::string(out.data());
}

bool password_matches(const std::string& hash, std::string_view password) {
  ensure_sodium();
  g_verifications.fetch_add(1, std::memory_order_relaxed);
  return crypto_pwhash_str_verify(hash.c_str(), password.data(), password.size()) == 0;
}

std::uint64_t password_verifications() {
  return g_verifications.load(std::memory_order_relaxed);
}

bool needs_rehash(const std::string& hash, PasswordCost cost) {
  ensure_sodium();
  const Limits limits = limits_of(cost);
  return crypto_pwhash_str_needs_rehash(hash.c_str(), limits.ops, limits.memory) != 0;
}

std::string random_hex(std::size_t count) {
  ensure_sodium();
  std::vector<unsigned char> bytes(count);
  randombytes_buf(bytes.data(), bytes.size());
  std::string hex(2 * count + 1, '\0');
  sodium_bin2hex(hex.data(), hex.size(), bytes.data(), bytes.size());
  sodium_memzero(bytes.data(), bytes.size());
  hex.pop_back();  // the terminating NUL
  return hex;
}

std::string random_token() {
  return random_hex(kTokenBytes);
}

std::string token_hash(std::string_view token) {
  ensure_sodium();
  if (token.size() != 2 * kTokenBytes) return {};
  std::array<unsigned char, kTokenBytes> bytes{};
  for (std::size_t i = 0; i < token.size(); ++i) {
    const char c = token[i];
    const bool hex_digit = (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
    if (!hex_digit) return {};  // lowercase only: one text form per token
  }
  std::size_t length = 0;
  if (sodium_hex2bin(bytes.data(), bytes.size(), token.data(), token.size(), nullptr, &length,
                     nullptr) != 0 ||
      length != kTokenBytes) {
    return {};
  }
  std::array<unsigned char, crypto_hash_sha256_BYTES> digest{};
  crypto_hash_sha256(digest.data(), bytes.data(), bytes.size());
  return std::string(reinterpret_cast<const char*>(digest.data()), digest.size());
}

}  // namespace ricochet::db
