#include "ricochet/bot/server_trust.h"

#include <openssl/evp.h>

#include <cctype>
#include <fstream>
#include <system_error>

namespace ricochet::bot {
namespace {

constexpr std::size_t kDigestBytes = 32;
constexpr char kHex[] = "0123456789ABCDEF";

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

}  // namespace

std::string certificate_fingerprint_sha256(X509* certificate) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int size = 0;
  if (!certificate || X509_digest(certificate, EVP_sha256(), digest, &size) != 1) return {};
  std::string text;
  text.reserve(size * 3);
  for (unsigned int i = 0; i < size; ++i) {
    if (i) text += ':';
    text += kHex[digest[i] >> 4];
    text += kHex[digest[i] & 0xf];
  }
  return text;
}

std::optional<std::string> normalize_fingerprint(std::string_view text) {
  std::string out;
  std::size_t pairs = 0;
  std::size_t i = 0;
  while (i < text.size()) {
    if (text[i] == ':') {
      if (pairs == 0 || (i + 1 < text.size() && text[i + 1] == ':')) return std::nullopt;
      ++i;
      continue;
    }
    if (i + 1 >= text.size() || hex_value(text[i]) < 0 || hex_value(text[i + 1]) < 0) {
      return std::nullopt;
    }
    if (pairs) out += ':';
    out += kHex[hex_value(text[i])];
    out += kHex[hex_value(text[i + 1])];
    ++pairs;
    i += 2;
  }
  if (pairs != kDigestBytes) return std::nullopt;
  return out;
}

ServerTrust ServerTrust::pinned(std::string fingerprint, std::string source) {
  ServerTrust trust;
  trust.trusted_ = std::move(fingerprint);
  trust.source_ = std::move(source);
  return trust;
}

ServerTrust ServerTrust::on_first_use(std::filesystem::path file) {
  ServerTrust trust;
  trust.file_ = std::move(file);
  return trust;
}

std::string ServerTrust::check(const std::string& fingerprint) {
  if (fingerprint.empty()) return "the server presented no certificate";
  if (trusted_.empty() && !file_.empty()) {
    std::ifstream in(file_);
    if (in) {
      std::string line;
      std::getline(in, line);
      const auto stored = normalize_fingerprint(line);
      if (!stored) {
        return "trust file " + file_.string() +
               " does not hold a SHA-256 fingerprint (32 hex pairs); fix or delete it";
      }
      trusted_ = *stored;
    } else {
      std::error_code ignored;
      if (std::filesystem::exists(file_, ignored)) {
        return "cannot read the trust file " + file_.string();
      }
      std::ofstream out(file_);
      out << fingerprint << '\n';
      if (!out) return "cannot write the trust file " + file_.string();
      trusted_ = fingerprint;
      return {};
    }
  }
  if (fingerprint != trusted_) {
    std::string where = file_.empty() ? source_ : "the trust file " + file_.string();
    return "the server's certificate SHA-256 " + fingerprint + " is not the trusted " + trusted_ +
           " (from " + where + "); if the server's certificate changed on purpose, update " + where;
  }
  return {};
}

}  // namespace ricochet::bot
