// libFuzzer target for the game channel's packet reader (proto/src/packet.cpp) and both
// endpoints' receive paths. The first byte picks what the rest is:
//   0  a datagram to the server from the connected client's address
//   1  a datagram to the server from a stranger
//   2  a datagram to the connected client from the server's address
//   3  byte 1 a packet type, bytes 2..9 a sequence, the rest a body sealed under the client's
//      client-to-server key: reaches the server's parsers behind the decryption
//   4  the same under the server-to-client key, to the client
// Every input must be dropped and counted or accepted; a crash, a sanitizer report, a datagram
// over 1200 bytes out, or a reply to a stranger larger than its cause is a bug. Run it with
// tools/fuzz.sh --only packet_reader.

#include <cstddef>
#include <cstdint>
#include <span>

#include "ricochet/proto/packet.h"
#include "transport_fuzz.h"

namespace {

using namespace ricochet::proto;

void parse_everything(std::span<const std::uint8_t> bytes) {
  (void)read_connection_request(bytes);
  (void)read_encrypted_header(bytes);
  (void)read_challenge_body(bytes);
  (void)read_denied_body(bytes);
  (void)read_keep_alive_body(bytes);
  (void)read_disconnect_body(bytes);
  auto payload = read_payload_body(bytes);
  if (payload.ok()) {
    // What parses re-encodes to the same bytes: the layout has one spelling.
    auto again = write_payload_body(payload.value);
    if (again.size() != bytes.size() || !std::equal(again.begin(), again.end(), bytes.begin())) {
      fuzz::fail("payload body did not re-encode to its bytes");
    }
  }
}

void check_server_output(GameServer& server, std::size_t cause_bytes, bool stranger) {
  Transmit transmit;
  while (server.poll_transmit(transmit)) {
    if (transmit.bytes.size() > kMaxDatagramBytes) fuzz::fail("server sent over 1200 bytes");
    if (stranger && transmit.bytes.size() > cause_bytes) fuzz::fail("reply larger than its cause");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::span<const std::uint8_t> rest(data + 1, size - 1);
  parse_everything(rest);
  fuzz::Session session;
  const TimeUs later = fuzz::kNow + 1000;
  switch (data[0] % 5) {
    case 0:
      session.server->receive(fuzz::kClientAddress, rest, later);
      check_server_output(*session.server, rest.size(), false);
      break;
    case 1:
      session.server->receive(Address::ipv4(192, 0, 2, 1, 9), rest, later);
      check_server_output(*session.server, rest.size(), true);
      break;
    case 2:
      session.client->receive(fuzz::kServerAddress, rest, later);
      break;
    case 3:
    case 4: {
      if (rest.size() < 9) return 0;
      const auto type = static_cast<PacketType>(rest[0] % kPacketTypeCount);
      std::uint64_t sequence = 0;
      for (int i = 0; i < 8; ++i) sequence |= std::uint64_t{rest[1 + i]} << (8 * i);
      const auto body = rest.subspan(9);
      if (body.size() > kMaxBodyBytes) return 0;
      if (data[0] % 5 == 3) {
        session.server->receive(
            fuzz::kClientAddress,
            seal_packet(type, sequence, fuzz::kProtocolId, session.grant.client_to_server, body),
            later);
        check_server_output(*session.server, 0, false);
      } else {
        session.client->receive(
            fuzz::kServerAddress,
            seal_packet(type, sequence, fuzz::kProtocolId, session.grant.server_to_client, body),
            later);
      }
      break;
    }
  }
  session.server->update(later + 200 * kMicrosPerMilli);
  session.client->update(later + 200 * kMicrosPerMilli);
  session.pump();
  session.drain();
  return 0;
}
