#pragma once
/// Wrong tokens at the admin port's POST /signin, limited per address (proto::HostKey: an IPv4
/// address or an IPv6 /64): at most `max_failures` in a window that opens at an address's first
/// failure and lasts `window_us`. Once an address has used them up it is refused until its window
/// ends, without its token being compared (AdminHttp answers 429 with Retry-After), so a guesser
/// gets max_failures guesses per window and learns nothing from the rest. Other addresses are
/// not affected: each has a window of its own.
///
/// Memory: at most `max_addresses` windows; one more address forgets the window that opened
/// first (a spray of addresses cannot grow the table, and the address forgotten gets a fresh
/// budget no larger than a new address's); a window that ended goes then, or at its address's
/// next failure. Time is passed in (µs, on the admin port's clock). Not thread-safe: AdminHttp
/// calls it on its strand.

#include <cstddef>
#include <cstdint>
#include <unordered_map>

#include "ricochet/proto/address.h"
#include "ricochet/proto/clock.h"

namespace ricochet::server {

class AdminSignInLimiter {
 public:
  /// `max_failures` >= 1, `window_us` > 0, `max_addresses` >= 1.
  AdminSignInLimiter(int max_failures, proto::TimeUs window_us, std::size_t max_addresses);

  /// How long `host` must wait before its next sign-in is looked at, in µs; 0: it may try now.
  proto::TimeUs wait_us(const proto::HostKey& host, proto::TimeUs now) const;
  /// One wrong token from `host`.
  void fail(const proto::HostKey& host, proto::TimeUs now);
  /// Addresses whose window is held now.
  std::size_t addresses() const { return windows_.size(); }

 private:
  struct Window {
    proto::TimeUs opened = 0;  ///< the first failure's time
    int failures = 0;
  };

  int max_failures_;
  proto::TimeUs window_us_;
  std::size_t max_addresses_;
  std::unordered_map<proto::HostKey, Window, proto::HostKeyHash> windows_;
};

}  // namespace ricochet::server
