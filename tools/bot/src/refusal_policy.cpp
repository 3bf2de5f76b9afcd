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

PlacementAction placement_action(wire::ErrorCode code) {
  switch (code) {
    case wire::MATCH_FULL:
    case wire::UNKNOWN_TICKET:
    case wire::EXPIRED_TICKET:
    case wire::MATCH_NOT_FOUND:
    case wire::ADDRESS_SEAT_LIMIT:
      return PlacementAction::FindAgain;
    case wire::NO_SERVER_AVAILABLE:
    case wire::FIND_MATCH_RATE_LIMITED:
    case wire::SERVER_BUSY:
      return PlacementAction::RetryLater;
    case wire::UNKNOWN_MODE_OR_MAP:
    case wire::INVALID_REQUEST:
      return PlacementAction::GiveUp;
    default:
      return PlacementAction::FailedAttempt;
  }
}

double find_again_s(int attempt, double unit) {
  constexpr double kFirstS = 0.25;
  constexpr double kLastS = 2;
  const double base = std::min(kLastS, kFirstS * std::pow(2.0, std::clamp(attempt, 1, 16) - 1));
  return base * (0.5 + std::clamp(unit, 0.0, 1.0));
}

double retry_later_s(double unit) {
  constexpr double kBaseS = 2;
  return kBaseS * (0.5 + std::clamp(unit, 0.0, 1.0));
}

double busy_backoff_s(int attempt, double unit) {
  constexpr double kFirstS = 0.5;
  constexpr double kLastS = 8;
  const double base = std::min(kLastS, kFirstS * std::pow(2.0, std::clamp(attempt, 1, 16) - 1));
  return base * (0.5 + std::clamp(unit, 0.0, 1.0));
}

}  // namespace ricochet::bot
