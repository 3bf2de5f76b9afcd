#pragma once
/// Logs abuse once per episode, not once per packet: an attacker who is refused 80 000 times a
/// second must not also flood the log. The first refusal of a (reason, key) pair starts an
/// episode and is logged at warn; later refusals of the pair are only counted, until the pair
/// has been quiet for `quiet_us`. The next refusal after that logs the episode's end (how many
/// refusals it had) and starts a new one. Counting for /metrics stays with the caller.
///
/// A key is what the limit counts under: an account ("account 42") or an address
/// (proto::HostKey::to_string()). At most `max_keys` episodes are tracked; beyond that, refusals
/// share the key "(many)", so memory stays bounded under a spoofed flood. Time is passed in (µs,
/// steady clock). Thread-safe: the control strand, match strands and the game channel share one.

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <string>
#include <string_view>
#include <unordered_map>

#include "ricochet/proto/clock.h"

namespace ricochet::server {

class EpisodeLog {
 public:
  explicit EpisodeLog(proto::TimeUs quiet_us = 10 * proto::kMicrosPerSecond,
                      std::size_t max_keys = 1024);

  /// One refusal of `reason` ("chat_flood") for `key`; `detail` says what was exceeded and is
  /// logged only when this starts an episode. True when it did.
  bool refuse(std::string_view reason, std::string_view key, std::string_view detail,
              proto::TimeUs now);

  /// Episodes open now (each a (reason, key) pair refused within the last quiet_us).
  std::size_t open_episodes(proto::TimeUs now);

 private:
  struct Episode {
    proto::TimeUs started = 0;
    proto::TimeUs last = 0;
    std::uint64_t refusals = 0;
  };
  void forget_quiet(proto::TimeUs now);
  static void log_end(const std::string& id, const Episode& episode);

  proto::TimeUs quiet_us_;
  std::size_t max_keys_;
  std::mutex mutex_;
  std::unordered_map<std::string, Episode> episodes_;  ///< by "reason key"
  proto::TimeUs next_sweep_ = 0;
};

}  // namespace ricochet::server
