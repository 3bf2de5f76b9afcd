#include "ricochet/proto/connect_token.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "byte_io.h"

namespace ricochet::proto {
std::vector<std::uint8_t> encode_connect_token_plaintext(const ConnectTokenContents& contents) {
  std::vector<std::uint8_t> out;
  out.reserve(kConnectTokenPlainBytes);
  ByteWriter writer(out);
  writer.u64(contents.account_id);
  writer.u32(contents.match_id);
  writer.u64(static_cast<std::uint64_t>(contents.expires_at));
  writer.u32(contents.timeout_s);
  writer.bytes(contents.client_to_server);
  writer.bytes(contents.server_to_client);
  return out;
}

Parsed<ConnectTokenContents> decode_connect_token_plaintext(std::span<const std::uint8_t> plain) {
  Parsed<ConnectTokenContents> out;
  if (plain.size() != kConnectTokenPlainBytes) {
    out.error = DropReason::Malformed;
    return out;
  }
  ByteReader reader(plain);
  out.value.account_id = reader.u64();
  out.value.match_id = reader.u32();
  out.value.expires_at = static_cast<TimeUs>(reader.u64());
  out.value.timeout_s = reader.u32();
  reader.copy_to(out.value.client_to_server);
  reader.copy_to(out.value.server_to_client);
  if (out.value.timeout_s < kMinTimeoutS || out.value.timeout_s > kMaxTimeoutS) {
    out.error = DropReason::Malformed;
  }
  return out;
}

TokenGrant issue_connect_token(const Key& token_key, std::uint64_t protocol_id,
                               std::uint64_t account_id, std::uint32_t match_id, TimeUs now,
                               TimeUs lifetime_us, std::uint32_t timeout_s) {
  if (lifetime_us <= 0 || lifetime_us > kMaxTokenLifetimeUs) {
    throw std::invalid_argument("connect token lifetime_us must be in (0, 30000000], got " +
                                std::to_string(lifetime_us));
  }
  if (timeout_s < kMinTimeoutS || timeout_s > kMaxTimeoutS) {
    throw std::invalid_argument("connect token timeout_s must be in [1, 60], got " +
                                std::to_string(timeout_s));
  }
  ConnectTokenContents contents;
  contents.account_id = account_id;
  contents.match_id = match_id;
  contents.expires_at = now + lifetime_us;
  contents.timeout_s = timeout_s;
  contents.client_to_server = random_key();
  contents.server_to_client = random_key();

  TokenGrant grant;
  XNonce nonce;
  fill_random(nonce);
  grant.connect_token.assign(nonce.begin(), nonce.end());
  seal_xchacha(encode_connect_token_plaintext(contents), version_and_protocol(protocol_id), nonce,
               token_key, grant.connect_token);
  grant.client_to_server = contents.client_to_server;
  grant.server_to_client = contents.server_to_client;
  grant.expires_at = contents.expires_at;
  grant.timeout_s = timeout_s;
  return grant;
}

Parsed<OpenedConnectToken> open_connect_token(const Key& token_key, std::uint64_t protocol_id,
                                              std::span<const std::uint8_t> token, TimeUs now) {
  Parsed<OpenedConnectToken> out;
  if (token.size() != kConnectTokenBytes) {
    out.error = DropReason::Malformed;
    return out;
  }
  XNonce nonce;
  std::copy_n(token.begin(), kXNonceBytes, nonce.begin());
  std::vector<std::uint8_t> plain;
  if (!open_xchacha(token.subspan(kXNonceBytes), version_and_protocol(protocol_id), nonce,
                    token_key, plain)) {
    out.error = DropReason::TokenInvalid;
    return out;
  }
  auto contents = decode_connect_token_plaintext(plain);
  if (!contents.ok()) {
    out.error = DropReason::TokenInvalid;
    return out;
  }
  out.value.contents = contents.value;
  std::copy_n(token.end() - kMacBytes, kMacBytes, out.value.mac.begin());
  if (now >= contents.value.expires_at || contents.value.expires_at - now > kMaxTokenLifetimeUs) {
    out.error = DropReason::TokenExpired;
  }
  return out;
}

}  // namespace ricochet::proto
