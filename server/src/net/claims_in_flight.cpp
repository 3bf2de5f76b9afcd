#include "claims_in_flight.h"

#include <algorithm>
#include <utility>

namespace ricochet::server {

ClaimsInFlight::ClaimsInFlight(Clock clock) : clock_(std::move(clock)) {}

ClaimsInFlight::Claim::~Claim() {
  owner_.end(id_);
}

ClaimsInFlight::Claim ClaimsInFlight::begin() {
  const std::lock_guard lock(mutex_);
  const db::UnixMillis now = clock_();
  const std::uint64_t id = next_id_++;
  claimed_ms_.emplace(id, now);
  return Claim(*this, id, now);
}

db::UnixMillis ClaimsInFlight::counted_as_of() const {
  const std::lock_guard lock(mutex_);
  db::UnixMillis as_of = clock_();
  for (const auto& [id, claimed_ms] : claimed_ms_) as_of = std::min(as_of, claimed_ms);
  return as_of;
}

std::size_t ClaimsInFlight::in_flight() const {
  const std::lock_guard lock(mutex_);
  return claimed_ms_.size();
}

void ClaimsInFlight::end(std::uint64_t id) {
  const std::lock_guard lock(mutex_);
  claimed_ms_.erase(id);
}

}  // namespace ricochet::server
