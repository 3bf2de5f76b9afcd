// libFuzzer target for the connect-token parser (proto/src/connect_token.cpp). The first byte
// picks what the rest is:
//   0  a sealed token, opened under the fuzz key at a time from the token's own expiry field
//      when it decodes, else at kNow
//   1  a token plaintext (after decryption): decoded, and if valid re-encoded to the same bytes
//   2  a token plaintext sealed under the fuzz key, then sent in a connection request to a
//      server: reaches the server's token checks (expiry, reuse, caps) with valid MACs
// Run it with tools/fuzz.sh --only connect_token.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>

#include "ricochet/proto/crypto.h"
#include "ricochet/proto/packet.h"
#include "transport_fuzz.h"

namespace {

using namespace ricochet::proto;

/// The same layout as the sealing in connect_token.cpp: nonce | AEAD(plaintext), with the
/// version and protocol id as additional data.
std::vector<std::uint8_t> seal_token(std::span<const std::uint8_t> plain) {
  const VersionAndProtocol ad = version_and_protocol(fuzz::kProtocolId);
  XNonce nonce{};
  nonce[0] = 1;
  std::vector<std::uint8_t> token(nonce.begin(), nonce.end());
  seal_xchacha(plain, ad, nonce, fuzz::token_key(), token);
  return token;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::span<const std::uint8_t> rest(data + 1, size - 1);
  switch (data[0] % 3) {
    case 0: {
      auto opened = open_connect_token(fuzz::token_key(), fuzz::kProtocolId, rest, fuzz::kNow);
      if (opened.ok() && opened.value.contents.expires_at <= fuzz::kNow) {
        fuzz::fail("an expired token opened");
      }
      break;
    }
    case 1: {
      auto decoded = decode_connect_token_plaintext(rest);
      if (decoded.ok()) {
        auto again = encode_connect_token_plaintext(decoded.value);
        if (!std::equal(again.begin(), again.end(), rest.begin(), rest.end())) {
          fuzz::fail("token plaintext did not re-encode to its bytes");
        }
      }
      break;
    }
    case 2: {
      GameServer server(fuzz::server_config());
      const auto request = write_connection_request(fuzz::kProtocolId, seal_token(rest));
      if (request.size() != kConnectionRequestBytes) break;  // a plaintext too long for a token
      server.receive(fuzz::kClientAddress, request, fuzz::kNow);
      server.receive(Address::ipv4(10, 5, 5, 5, 5), request, fuzz::kNow);
      Transmit transmit;
      while (server.poll_transmit(transmit)) {
        if (transmit.bytes.size() > request.size()) fuzz::fail("reply larger than the request");
      }
      server.update(fuzz::kNow + 6 * kMicrosPerSecond);
      break;
    }
  }
  return 0;
}
