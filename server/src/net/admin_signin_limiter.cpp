#include "admin_signin_limiter.h"

#include <algorithm>

namespace ricochet::server {

AdminSignInLimiter::AdminSignInLimiter(int max_failures, proto::TimeUs window_us,
                                       std::size_t max_addresses)
    : max_failures_(std::max(max_failures, 1)),
      window_us_(std::max<proto::TimeUs>(window_us, 1)),
      max_addresses_(std::max<std::size_t>(max_addresses, 1)) {}

proto::TimeUs AdminSignInLimiter::wait_us(const proto::HostKey& host, proto::TimeUs now) const {
  const auto found = windows_.find(host);
  if (found == windows_.end() || found->second.failures < max_failures_) return 0;
  return std::max<proto::TimeUs>(found->second.opened + window_us_ - now, 0);
}

void AdminSignInLimiter::fail(const proto::HostKey& host, proto::TimeUs now) {
  auto found = windows_.find(host);
  if (found != windows_.end() && found->second.opened + window_us_ <= now) {  // ended
    windows_.erase(found);
    found = windows_.end();
  }
  if (found == windows_.end()) {
    if (windows_.size() >= max_addresses_) {  // an ended window, if any, is the oldest
      windows_.erase(std::min_element(
          windows_.begin(), windows_.end(),
          [](const auto& a, const auto& b) { return a.second.opened < b.second.opened; }));
    }
    found = windows_.emplace(host, Window{now, 0}).first;
  }
  found->second.failures = std::min(found->second.failures + 1, max_failures_);
}

}  // namespace ricochet::server
