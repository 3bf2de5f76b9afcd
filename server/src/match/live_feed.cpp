/// The hand-off of a match's live frames (live_frame.h).

#include <utility>

#include "ricochet/server/live_frame.h"

namespace ricochet::server {

const char* name(LiveProjectileKind kind) {
  switch (kind) {
    case LiveProjectileKind::Rocket:
      return "rocket";
    case LiveProjectileKind::Grenade:
      return "grenade";
  }
  return "unknown";
}

std::string LiveFeedConfig::validate() const {
  if (rate_hz < 1 || rate_hz > 60) {
    return "rate_hz must be 1..60, got " + std::to_string(rate_hz);
  }
  if (max_viewers < 1 || max_viewers > 64) {
    return "max_viewers must be 1..64, got " + std::to_string(max_viewers);
  }
  return {};
}

LiveFeed::LiveFeed(const LiveFeedConfig& config)
    : interval_us_(proto::kMicrosPerSecond / config.rate_hz), max_viewers_(config.max_viewers) {}

std::optional<LiveFeed::Viewer> LiveFeed::watch() {
  int seated = viewers_.load(std::memory_order_relaxed);
  do {
    if (seated >= max_viewers_) return std::nullopt;
  } while (!viewers_.compare_exchange_weak(seated, seated + 1, std::memory_order_acq_rel));
  return Viewer(shared_from_this());
}

void LiveFeed::leave() {
  if (viewers_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
    const std::lock_guard lock(mutex_);
    latest_.reset();
  }
}

void LiveFeed::publish(std::shared_ptr<const LiveFrame> frame) {
  std::shared_ptr<const LiveFrame> replaced;  // freed outside the lock
  const std::lock_guard lock(mutex_);
  if (!watched()) return;
  replaced = std::exchange(latest_, std::move(frame));
}

std::shared_ptr<const LiveFrame> LiveFeed::latest() const {
  const std::lock_guard lock(mutex_);
  return latest_;
}

LiveFeed::Viewer::Viewer(Viewer&& other) noexcept : feed_(std::move(other.feed_)) {}

LiveFeed::Viewer& LiveFeed::Viewer::operator=(Viewer&& other) noexcept {
  if (this != &other) {
    if (feed_) feed_->leave();
    feed_ = std::move(other.feed_);
  }
  return *this;
}

LiveFeed::Viewer::~Viewer() {
  if (feed_) feed_->leave();
}

std::shared_ptr<const LiveFrame> LiveFeed::Viewer::latest() const {
  return feed_ ? feed_->latest() : nullptr;
}

}  // namespace ricochet::server
