#include "control_config.h"

#include <boost/asio/ip/address.hpp>
#include <string>

namespace ricochet::server {
namespace {

template <class T>
std::string out_of_range(const char* field, const std::string& range, T value) {
  return std::string("control.") + field + " must be " + range + ", got " + std::to_string(value);
}

}  // namespace

std::string ControlLimits::validate() const {
  if (max_connections < 1 || max_connections > 1'000'000) {
    return out_of_range("max_connections", "1..1000000", max_connections);
  }
  if (max_connections_per_address < 1 || max_connections_per_address > max_connections) {
    return out_of_range("max_connections_per_address",
                        "1..max_connections (" + std::to_string(max_connections) + ")",
                        max_connections_per_address);
  }
  const std::pair<const char*, std::uint32_t> timeouts[] = {
      {"handshake_timeout_ms", handshake_timeout_ms}, {"frame_timeout_ms", frame_timeout_ms},
      {"idle_timeout_ms", idle_timeout_ms},           {"login_timeout_ms", login_timeout_ms},
      {"write_timeout_ms", write_timeout_ms},
  };
  for (const auto& [field, value] : timeouts) {
    if (value < 10 || value > 3'600'000) return out_of_range(field, "10..3600000", value);
  }
  if (!(messages_per_second > 0 && messages_per_second <= 10'000)) {
    return out_of_range("messages_per_second", "> 0 and <= 10000", messages_per_second);
  }
  if (message_burst < 1 || message_burst > 10'000) {
    return out_of_range("message_burst", "1..10000", message_burst);
  }
  if (max_outbox_bytes < 128 * 1024) {
    return out_of_range("max_outbox_bytes", ">= 131072 (two largest frames)", max_outbox_bytes);
  }
  return {};
}

std::string ControlServerConfig::validate() const {
  boost::system::error_code error;
  boost::asio::ip::make_address(bind_address, error);
  if (error) {
    return "control.bind_address must be an IPv4 or IPv6 address, got '" + bind_address + "'";
  }
  return limits.validate();
}

}  // namespace ricochet::server
