#pragma once
/// What a soak is told on top of the load test's options (loadtest_config.h): the bad link every
/// bot plays through, how bots come and go, the warm-up left out of the slopes and the bounds
/// that call the server's RSS and open descriptors flat. validate() explains what is wrong.

#include <string>

#include "ricochet/bot/link_simulator.h"
#include "ricochet/loadtest/flatness.h"
#include "ricochet/loadtest/loadtest_config.h"

namespace ricochet::loadtest {

/// The server's default `db.registrations_per_hour_per_address`: fresh accounts of the bots of
/// one source address must stay under it, or their registrations are refused.
inline constexpr double kServerRegistrationsPerHourPerAddress = 10;

/// Flat for an hour-long soak at about 40 bots with churn and matches of a few minutes, where
/// the server makes about 1,700 game connections, 400 sign-ins and 60 matches an hour:
/// - RSS 16 MiB/h: a leak of 16 KiB per game connection grows about 27 MiB/h, one of 100 bytes
///   per snapshot sent (2,400 a second) about 820 MiB/h; what a healthy server's allocator
///   still gains after the warm-up is a few MiB at most.
/// - 10 fds/h: one descriptor leaked per match (a recording file) adds about 60 an hour, one
///   per sign-in (a TLS socket) about 400; bots coming and going move the count by a few
///   either way, which a fit over an hour turns into much less than 10 an hour.
inline constexpr FlatnessBounds kHourSoakBounds{16.0, 10.0};

/// How bots come and go: each slot's bot leaves (a clean disconnect) after a lifetime drawn
/// uniformly from [min_life_s, max_life_s] and a new bot takes the slot at once, signing in
/// with the password: on the slot's last account, or with probability new_account_share on a
/// new one (registered first).
struct ChurnConfig {
  double min_life_s = 60;
  double max_life_s = 600;  ///< 0: no churn (every bot stays for the whole run)
  double new_account_share = 0.1;

  bool active() const { return max_life_s > 0; }
  double mean_life_s() const { return (min_life_s + max_life_s) / 2; }
  /// Accounts the bots of one source address register in the first hour of a run of
  /// `duration_s`, expected: the slots' first accounts and the new ones of the returns (the
  /// server's limit is per sliding hour, and no later hour registers more).
  double registrations_in_an_hour(int bots_per_address, double duration_s) const;
  std::string validate() const;
};

struct SoakConfig {
  /// Each direction of every bot's game channel (the control channel is TCP and unimpaired).
  bot::LinkConfig link{200, 50, 0.2, 0.05, 0.05};
  ChurnConfig churn;
  /// Samples before this are left out of the slopes; < 0: max(10 % of the duration, 60 s).
  double warmup_s = -1;
  FlatnessBounds bounds = kHourSoakBounds;

  /// The warm-up used for a run of `duration_s` measured seconds.
  double warmup_for(double duration_s) const;
  /// Empty when usable with `run` (the load test's options: bots per address, duration);
  /// otherwise the first wrong field, its range and its value.
  std::string validate(const LoadTestConfig& run) const;
};

}  // namespace ricochet::loadtest
