#pragma once
/// A datagram an endpoint wants sent. Endpoints queue them; the socket layer drains them with
/// poll_transmit after every call into the endpoint.

#include <cstdint>
#include <vector>

#include "ricochet/proto/address.h"

namespace ricochet::proto {

struct Transmit {
  Address to;
  std::vector<std::uint8_t> bytes;  ///< at most kMaxDatagramBytes
};

}  // namespace ricochet::proto
