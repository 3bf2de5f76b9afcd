#pragma once
/// libsodium in one place: Argon2id password hashes, random session tokens and their SHA-256.

#include <cstdint>
#include <string>
#include <string_view>

#include "ricochet/db/accounts.h"
#include "ricochet/db/result.h"

namespace ricochet::db {

/// crypto_pwhash_str (Argon2id) at the cost's ops and memory limits. OutOfMemory when libsodium
/// could not allocate the memory the cost asks for.
DbResult<std::string> hash_password(std::string_view password, PasswordCost cost);
/// True when the password matches the crypto_pwhash_str hash (constant time in the password).
/// Thread-safe; every call is counted in password_verifications().
bool password_matches(const std::string& hash, std::string_view password);
/// Argon2id verifications this process has run so far, from any thread (for tests: an unknown
/// name must cost one, like a wrong password).
std::uint64_t password_verifications();
/// True when the hash was made with other limits than `cost` (rehash it at the next login).
bool needs_rehash(const std::string& hash, PasswordCost cost);

/// `count` random bytes from libsodium's CSPRNG, as 2 * count lowercase hex digits.
std::string random_hex(std::size_t count);
/// kTokenBytes random bytes from libsodium's CSPRNG, as lowercase hex.
std::string random_token();
/// SHA-256 of the token's bytes (32 raw bytes); empty when the text is not kTokenBytes of hex.
std::string token_hash(std::string_view token);

}  // namespace ricochet::db
