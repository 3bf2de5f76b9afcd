#include "heartbeat_schedule.h"

#include <algorithm>

namespace ricochet::server {

HeartbeatSchedule::HeartbeatSchedule(proto::TimeUs period_us, proto::TimeUs ttl_us,
                                     proto::TimeUs now)
    : period_us_(period_us), ttl_us_(ttl_us), next_at_(now) {}

bool HeartbeatSchedule::start(proto::TimeUs now) {
  if (stopped_ || in_flight_since_ || now < next_at_) return false;
  in_flight_since_ = now;
  last_began_ = now;
  next_at_ = now + period_us_;
  return true;
}

void HeartbeatSchedule::changed(proto::TimeUs now) {
  const proto::TimeUs earliest = last_began_ ? *last_began_ + period_us_ / 4 : now;
  next_at_ = std::min(next_at_, std::max(now, earliest));
}

DirectoryListing HeartbeatSchedule::finished(bool written, proto::TimeUs now) {
  if (!in_flight_since_) return DirectoryListing::Unchanged;
  const proto::TimeUs began = *in_flight_since_;
  in_flight_since_.reset();
  if (written) {
    last_written_ = began;
    if (reported_listed_) return DirectoryListing::Unchanged;
    reported_listed_ = true;
    return DirectoryListing::Listed;
  }
  if (reported_listed_ && !listed(now)) {
    reported_listed_ = false;
    return DirectoryListing::Lost;
  }
  return DirectoryListing::Unchanged;
}

std::optional<proto::TimeUs> HeartbeatSchedule::next_at() const {
  if (stopped_ || in_flight_since_) return std::nullopt;
  return next_at_;
}

bool HeartbeatSchedule::listed(proto::TimeUs now) const {
  return !stopped_ && last_written_ && now - *last_written_ < ttl_us_;
}

}  // namespace ricochet::server
