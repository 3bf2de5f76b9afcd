#include "episode_log.h"

#include <spdlog/spdlog.h>

namespace ricochet::server {

EpisodeLog::EpisodeLog(proto::TimeUs quiet_us, std::size_t max_keys)
    : quiet_us_(quiet_us), max_keys_(max_keys) {}

bool EpisodeLog::refuse(std::string_view reason, std::string_view key, std::string_view detail,
                        proto::TimeUs now) {
  const std::lock_guard lock(mutex_);
  if (now >= next_sweep_) forget_quiet(now);
  std::string id = std::string(reason) + ' ' + std::string(key);
  auto it = episodes_.find(id);
  if (it == episodes_.end() && episodes_.size() >= max_keys_) {
    id = std::string(reason) + " (many)";
    it = episodes_.find(id);
  }
  if (it != episodes_.end() && now - it->second.last < quiet_us_) {
    ++it->second.refusals;
    it->second.last = now;
    return false;
  }
  if (it != episodes_.end()) log_end(it->first, it->second);
  episodes_[id] = Episode{now, now, 1};
  spdlog::warn("{} from {}: {} (further refusals counted, logged when it ends)", reason, key,
               detail);
  return true;
}

std::size_t EpisodeLog::open_episodes(proto::TimeUs now) {
  const std::lock_guard lock(mutex_);
  forget_quiet(now);
  return episodes_.size();
}

void EpisodeLog::log_end(const std::string& id, const Episode& episode) {
  if (episode.refusals <= 1) return;  // its one refusal was logged when it started
  spdlog::warn("{}: episode ended, {} refusals in {:.1f} s", id, episode.refusals,
               static_cast<double>(episode.last - episode.started) / 1e6);
}

void EpisodeLog::forget_quiet(proto::TimeUs now) {
  std::erase_if(episodes_, [&](const auto& entry) {
    const Episode& episode = entry.second;
    if (now - episode.last < quiet_us_) return false;
    log_end(entry.first, episode);
    return true;
  });
  next_sweep_ = now + quiet_us_;
}

}  // namespace ricochet::server
