#include "ricochet/loadtest/soak_config.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ricochet::loadtest {

namespace {

constexpr double kWarmupShare = 0.1;
constexpr double kMinWarmupS = 60;

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

bool within(double value, double low, double high) {
  return std::isfinite(value) && value >= low && value <= high;
}

}  // namespace

double ChurnConfig::registrations_in_an_hour(int bots_per_address, double duration_s) const {
  const double returns = active() ? std::min(duration_s, 3600.0) / mean_life_s() : 0;
  return bots_per_address * (1 + new_account_share * returns);
}

std::string ChurnConfig::validate() const {
  if (!within(max_life_s, 0, 86400))
    return "churn max life must be 0..86400 s, got " + number(max_life_s);
  if (!active()) return {};
  if (!within(min_life_s, 1, max_life_s)) {
    return "churn min life must be 1 s..the max life (" + number(max_life_s) + " s), got " +
           number(min_life_s);
  }
  if (!within(new_account_share, 0, 1)) {
    return "churn new account share must be 0..1, got " + number(new_account_share);
  }
  return {};
}

double SoakConfig::warmup_for(double duration_s) const {
  if (warmup_s >= 0) return warmup_s;
  return std::max(kWarmupShare * duration_s, kMinWarmupS);
}

std::string SoakConfig::validate(const LoadTestConfig& run) const {
  if (std::string problem = link.validate(); !problem.empty()) return problem;
  if (std::string problem = churn.validate(); !problem.empty()) return problem;
  if (!run.sweep.empty()) return "a soak runs one step of bots, not a sweep";
  if (run.servers.size() != 1)
    return "a soak watches one server, got " + std::to_string(run.servers.size());
  if (!is_loopback_v4(run.servers.front().host)) {
    return "a soak reads the server's RSS from its /proc: the server must be on loopback";
  }
  const double registrations = churn.registrations_in_an_hour(run.bots_per_address, run.duration_s);
  if (registrations > kServerRegistrationsPerHourPerAddress) {
    return "the bots of one source address would register about " + number(registrations) +
           " accounts an hour, over the server's default of " +
           number(kServerRegistrationsPerHourPerAddress) +
           ": lower --bots-per-address or --churn-new-account, or lengthen the lives";
  }
  const double warmup = warmup_for(run.duration_s);
  if (!(warmup >= 0 && warmup < run.duration_s)) {
    return "the warm-up must be shorter than the duration (" + number(run.duration_s) +
           " s), got " + number(warmup) + " s";
  }
  if (!(bounds.rss_mib_per_hour > 0) || !(bounds.fds_per_hour > 0)) {
    return "the slope bounds must be > 0, got " + number(bounds.rss_mib_per_hour) + " MiB/h and " +
           number(bounds.fds_per_hour) + " fds/h";
  }
  return {};
}

}  // namespace ricochet::loadtest
