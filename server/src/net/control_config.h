#pragma once
/// What the control channel is configured with: where it listens, its TLS identity and the
/// limits that keep hostile or broken clients from holding resources. The operations config
/// (config.h) maps its TOML keys and flags onto this struct; defaults are the documented ones.

#include <cstdint>
#include <functional>
#include <string>

#include "episode_log.h"
#include "fleet_placement.h"
#include "ricochet/proto/clock.h"
#include "steady_time.h"
#include "tls_identity.h"

namespace ricochet::server {

struct ControlLimits {
  int max_connections = 4096;                  ///< open TLS connections in total (1..1'000'000)
  int max_connections_per_address = 16;        ///< from one IP address (1..max_connections)
  std::uint32_t handshake_timeout_ms = 5'000;  ///< accept to finished TLS handshake
  std::uint32_t frame_timeout_ms = 10'000;     ///< first byte of a frame to its last (slowloris)
  std::uint32_t idle_timeout_ms = 120'000;     ///< no whole frame for this long (clients ping)
  std::uint32_t login_timeout_ms = 30'000;     ///< handshake to login or resume; pings do not count
  std::uint32_t write_timeout_ms = 10'000;     ///< one reply may take this long to be sent
  double messages_per_second = 20;             ///< sustained requests per connection (> 0)
  int message_burst = 40;                      ///< requests a connection may send at once (>= 1)
  std::size_t max_outbox_bytes = 1 << 20;      ///< queued replies of a client that does not read

  /// Empty when valid, else which field is wrong, its allowed range and the value that came.
  std::string validate() const;
};

struct ControlServerConfig {
  std::string bind_address = "0.0.0.0";  ///< an IPv4 or IPv6 literal
  std::uint16_t port = 7777;             ///< 0: any free port (tests); see ControlServer::port()
  TlsIdentityPaths tls;                  ///< certificate and key, or the data directory
  ControlLimits limits;
  /// The clock every deadline, the message rate and connect tokens' expiry are on, in µs: the
  /// MatchDirectory must issue its tokens on it too. Tests pass fake time and call
  /// ControlServer::check_deadlines() after moving it.
  std::function<proto::TimeUs()> clock = steady_now_us;
  /// Logs the account refusals (login_timeout, login_rate_limited, registration_rate_limited,
  /// server_busy) once per episode per address; nullptr: they are only counted.
  EpisodeLog* episodes = nullptr;
  /// find_match and tickets across the fleet ([placement] on); nullptr: placement is off here.
  /// Used on the control strand; must outlive the ControlServer.
  FleetPlacement* placement = nullptr;

  std::string validate() const;
};

}  // namespace ricochet::server
