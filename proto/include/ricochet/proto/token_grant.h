#pragma once
/// What the control channel hands a client that joins a match: the connect token for the game
/// channel and the two session keys inside it (connect_token.h issues it; PROTOCOL.md §tokens).

#include <array>
#include <cstdint>
#include <vector>

#include "ricochet/proto/clock.h"

namespace ricochet::proto {

/// The game's protocol id ("RICOCHET" in ASCII): sealed into every connect token and sent in every
/// connection request; a server refuses another (PROTOCOL.md).
inline constexpr std::uint64_t kProtocolId = 0x5249434f43484554ull;

inline constexpr std::size_t kKeyBytes = 32;
using Key = std::array<std::uint8_t, kKeyBytes>;

struct TokenGrant {
  std::vector<std::uint8_t> connect_token;  ///< opaque to the client; sent as is in the request
  Key client_to_server{};                   ///< packets the client seals
  Key server_to_client{};                   ///< packets the server seals
  TimeUs expires_at = 0;                    ///< on the issuing server's clock
  std::uint32_t timeout_s = 0;              ///< silence after which either side drops the other
};

}  // namespace ricochet::proto
