#pragma once
/// Chat's rate limits (PROTOCOL.md Control channel §chat): per account, across every control
/// session it has open, and per match, across all its players, a token bucket each. A line over
/// either is refused (the sender gets RATE_LIMITED), counted by the limit it broke and logged
/// once per episode (EpisodeLog, reason "chat_flood"). Together they bound the chat every player
/// of a match receives, whatever the number of accounts or sessions sending it.
///
/// Thread-safe: control sessions call it from any thread. Time is passed in (µs, steady clock).
/// Memory: a bucket per account and match that chatted recently; full buckets are forgotten.

#include <array>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>

#include "episode_log.h"
#include "ricochet/proto/token_bucket.h"

namespace ricochet::server {

struct ChatLimits {
  double account_lines_per_s = 1;  ///< sustained lines per account (0.01..100)
  int account_burst = 5;           ///< lines an account may send at once (1..1000)
  double match_lines_per_s = 8;    ///< sustained lines per match, all players (0.01..1000)
  int match_burst = 20;            ///< lines a match may carry at once (1..1000)

  /// Empty when valid, else which field is wrong, its allowed range and the value that came.
  std::string validate() const;
};

/// Which limit refused a line.
enum class ChatLimit : std::uint8_t {
  Account,
  Match,
};
inline constexpr std::size_t kChatLimitCount = static_cast<std::size_t>(ChatLimit::Match) + 1;
const char* name(ChatLimit limit);

class ChatLimiter {
 public:
  /// Throws std::invalid_argument with validate()'s text. `episodes` outlives the limiter.
  ChatLimiter(ChatLimits limits, EpisodeLog& episodes);

  /// One line from `account` in match `match_id`: takes a token from the account's bucket, then
  /// from the match's. Which limit refused it, or nothing when it may be sent. A line the match
  /// refuses still costs the account its token.
  std::optional<ChatLimit> take(std::uint64_t account, std::uint32_t match_id, proto::TimeUs now);
  /// The limit, for the sender's Error and the log: "chat is limited to 1 line/s per account,
  /// bursts of 5".
  std::string explain(ChatLimit limit) const;
  /// Lines refused so far, by ChatLimit.
  std::array<std::uint64_t, kChatLimitCount> refusals() const;

 private:
  /// Forgets full buckets (as good as fresh ones). Holds mutex_.
  void sweep(proto::TimeUs now);

  ChatLimits limits_;
  EpisodeLog& episodes_;
  mutable std::mutex mutex_;
  std::unordered_map<std::uint64_t, proto::TokenBucket> accounts_;
  std::unordered_map<std::uint32_t, proto::TokenBucket> matches_;
  std::array<std::uint64_t, kChatLimitCount> refusals_{};
  proto::TimeUs next_sweep_ = 0;
};

}  // namespace ricochet::server
