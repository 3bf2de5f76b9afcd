// Writes the seed corpus of packet_reader_fuzz: every packet type as the endpoints really send
// it, behind the mode byte that packet_reader_fuzz.cpp reads. Run by `tools/fuzz.sh --seeds`;
// the output is committed in tests/fuzz/corpus/packet_reader/.
//
//   packet_reader_seeds DIR

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "ricochet/proto/packet.h"
#include "transport_fuzz.h"

namespace {

using namespace ricochet::proto;

std::vector<std::uint8_t> sealed_body_seed(PacketType type, std::uint64_t sequence,
                                           const std::vector<std::uint8_t>& body) {
  std::vector<std::uint8_t> out = {static_cast<std::uint8_t>(type)};
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<std::uint8_t>(sequence >> (8 * i)));
  out.insert(out.end(), body.begin(), body.end());
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: packet_reader_seeds DIR\n");
    return 2;
  }
  fuzz::SeedWriter writer{argv[1]};
  fuzz::Session session;
  // A real exchange captured from both ends.
  GameClient fresh(ClientConnectInfo{issue_connect_token(fuzz::token_key(), fuzz::kProtocolId, 9, 1,
                                                         fuzz::kNow, 30 * kMicrosPerSecond, 5),
                                     fuzz::kProtocolId, fuzz::kServerAddress},
                   fuzz::kNow);
  Transmit transmit;
  fresh.poll_transmit(transmit);
  writer.save("request_stranger", 1, transmit.bytes);
  session.server->receive(Address::ipv4(10, 7, 7, 7, 7), transmit.bytes, fuzz::kNow);
  session.server->poll_transmit(transmit);
  writer.save("challenge", 2, transmit.bytes);

  session.client->send_reliable(std::vector<std::uint8_t>{1, 2, 3}, fuzz::kNow);
  session.client->send_unreliable(std::vector<std::uint8_t>(40, 7), fuzz::kNow);
  session.client->poll_transmit(transmit);
  writer.save("payload_from_client", 0, transmit.bytes);
  session.client->disconnect(fuzz::kNow);
  session.client->poll_transmit(transmit);
  writer.save("disconnect_from_client", 0, transmit.bytes);
  session.server->send_unreliable(1, std::vector<std::uint8_t>(100, 3), fuzz::kNow);
  session.server->poll_transmit(transmit);
  writer.save("payload_from_server", 2, transmit.bytes);

  PayloadBody payload;
  payload.ack = {3, 0x7};
  payload.reliable = {{0, {5, 6}}, {1, {7}}};
  payload.unreliable = {1, 2, 3, 4};
  writer.save("sealed_payload_to_server", 3,
              sealed_body_seed(PacketType::Payload, 50, write_payload_body(payload)));
  writer.save("sealed_payload_to_client", 4,
              sealed_body_seed(PacketType::Payload, 50, write_payload_body(payload)));
  writer.save("sealed_keep_alive", 3,
              sealed_body_seed(PacketType::KeepAlive, 51, write_keep_alive_body({1, 1})));
  writer.save("sealed_disconnect", 4,
              sealed_body_seed(PacketType::Disconnect, 52,
                               write_disconnect_body({{}, DisconnectReason::Kicked})));
  writer.save("sealed_response", 3,
              sealed_body_seed(PacketType::Response, 53, write_challenge_body({})));
  writer.save("sealed_denied", 4,
              sealed_body_seed(PacketType::ConnectionDenied, kHandshakeSequenceBit | 1,
                               write_denied_body(DisconnectReason::Denied)));
  std::printf("packet_reader_seeds: wrote %d seeds into %s\n", writer.written, argv[1]);
  return 0;
}
