#include "chat_limiter.h"

#include <iterator>
#include <sstream>
#include <stdexcept>

namespace ricochet::server {

namespace {

/// How often full buckets are forgotten, µs: each sweep visits every bucket.
constexpr proto::TimeUs kSweepIntervalUs = 10 * proto::kMicrosPerSecond;

std::string out_of_range(const char* field, const char* range, double value) {
  std::ostringstream text;
  text << "chat " << field << " must be " << range << ", got " << value;
  return text.str();
}

}  // namespace

std::string ChatLimits::validate() const {
  if (!(account_lines_per_s >= 0.01 && account_lines_per_s <= 100)) {
    return out_of_range("account_lines_per_s", "0.01..100", account_lines_per_s);
  }
  if (account_burst < 1 || account_burst > 1000) {
    return out_of_range("account_burst", "1..1000", account_burst);
  }
  if (!(match_lines_per_s >= 0.01 && match_lines_per_s <= 1000)) {
    return out_of_range("match_lines_per_s", "0.01..1000", match_lines_per_s);
  }
  if (match_burst < 1 || match_burst > 1000) {
    return out_of_range("match_burst", "1..1000", match_burst);
  }
  return {};
}

const char* name(ChatLimit limit) {
  switch (limit) {
    case ChatLimit::Account:
      return "account";
    case ChatLimit::Match:
      return "match";
  }
  return "unknown";
}

ChatLimiter::ChatLimiter(ChatLimits limits, EpisodeLog& episodes)
    : limits_(limits), episodes_(episodes) {
  if (std::string problem = limits_.validate(); !problem.empty()) {
    throw std::invalid_argument(problem);
  }
}

std::optional<ChatLimit> ChatLimiter::take(std::uint64_t account, std::uint32_t match_id,
                                           proto::TimeUs now) {
  std::optional<ChatLimit> refused;
  std::string key;
  {
    const std::lock_guard lock(mutex_);
    if (now >= next_sweep_) sweep(now);
    auto& by_account =
        accounts_.try_emplace(account, limits_.account_lines_per_s, limits_.account_burst, now)
            .first->second;
    if (!by_account.take(now)) {
      refused = ChatLimit::Account;
      key = "account " + std::to_string(account);
    } else {
      auto& by_match =
          matches_.try_emplace(match_id, limits_.match_lines_per_s, limits_.match_burst, now)
              .first->second;
      if (!by_match.take(now)) {
        refused = ChatLimit::Match;
        key = "match " + std::to_string(match_id);
      }
    }
    if (!refused) return std::nullopt;
    ++refusals_[static_cast<std::size_t>(*refused)];
  }
  episodes_.refuse("chat_flood", key, explain(*refused), now);
  return refused;
}

std::string ChatLimiter::explain(ChatLimit limit) const {
  const bool per_account = limit == ChatLimit::Account;
  std::ostringstream text;
  text << "chat is limited to "
       << (per_account ? limits_.account_lines_per_s : limits_.match_lines_per_s) << " line/s per "
       << name(limit) << ", bursts of "
       << (per_account ? limits_.account_burst : limits_.match_burst);
  return text.str();
}

std::array<std::uint64_t, kChatLimitCount> ChatLimiter::refusals() const {
  const std::lock_guard lock(mutex_);
  return refusals_;
}

void ChatLimiter::sweep(proto::TimeUs now) {
  const auto forget_full = [now](auto& buckets) {
    for (auto it = buckets.begin(); it != buckets.end();) {
      it = it->second.full(now) ? buckets.erase(it) : std::next(it);
    }
  };
  forget_full(accounts_);
  forget_full(matches_);
  next_sweep_ = now + kSweepIntervalUs;
}

}  // namespace ricochet::server
