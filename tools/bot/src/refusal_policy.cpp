#include "ricochet/bot/refusal_policy.h"

#include <algorithm>
#include <cmath>

namespace ricochet::bot {

RefusalAction refusal_action(wire::ErrorCode code) {
  switch (code) {
    case wire::SERVER_BUSY:
      return RefusalAction::Retry;
    case wire::MATCH_FULL:
    case wire::ADDRESS_SEAT_LIMIT:
      return RefusalAction::WaitForRoom;
    default:
      return RefusalAction::FailedAttempt;
  }
}

double busy_backoff_s(int attempt, double unit) {
  constexpr double kFirstS = 0.5;
  constexpr double kLastS = 8;
  const double base = std::min(kLastS, kFirstS * std::pow(2.0, std::clamp(attempt, 1, 16) - 1));
  return base * (0.5 + std::clamp(unit, 0.0, 1.0));
}

}  // namespace ricochet::bot
