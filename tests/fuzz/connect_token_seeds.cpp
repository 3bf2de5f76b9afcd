// Writes the seed corpus of connect_token_fuzz: a token sealed under the fuzz key, its plaintext,
// and plaintexts at the edges (timeouts 1 and 60, an expiry in the past), behind the mode byte
// that connect_token_fuzz.cpp reads. Run by `tools/fuzz.sh --seeds`; the output is committed in
// tests/fuzz/corpus/connect_token/.
//
//   connect_token_seeds DIR

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "transport_fuzz.h"

namespace {

using namespace ricochet::proto;

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: connect_token_seeds DIR\n");
    return 2;
  }
  fuzz::SeedWriter writer{argv[1]};
  const TokenGrant grant = issue_connect_token(fuzz::token_key(), fuzz::kProtocolId, 1234, 2,
                                               fuzz::kNow, 30 * kMicrosPerSecond, 5);
  writer.save("sealed_token", 0, grant.connect_token);
  ConnectTokenContents contents;
  contents.account_id = 1234;
  contents.match_id = 2;
  contents.expires_at = fuzz::kNow + 10 * kMicrosPerSecond;
  contents.timeout_s = 5;
  contents.client_to_server = grant.client_to_server;
  contents.server_to_client = grant.server_to_client;
  writer.save("plaintext", 1, encode_connect_token_plaintext(contents));
  writer.save("plaintext_to_server", 2, encode_connect_token_plaintext(contents));
  contents.timeout_s = 1;
  writer.save("plaintext_timeout_1", 1, encode_connect_token_plaintext(contents));
  contents.timeout_s = 60;
  contents.expires_at = fuzz::kNow - 1;
  writer.save("expired_to_server", 2, encode_connect_token_plaintext(contents));
  std::printf("connect_token_seeds: wrote %d seeds into %s\n", writer.written, argv[1]);
  return 0;
}
