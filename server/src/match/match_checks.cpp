/// What a player's inputs claim, checked against what the rules allow (match_checks.h): aim that
/// turns faster than a person can, and the violations' counting and logging. The fire rate is
/// checked where weapons fire (match_combat.cpp), the input rate where inputs arrive (match.cpp).

#include "match_checks.h"

#include <cmath>
#include <numbers>

namespace ricochet::server {

namespace {

/// a - b wrapped into (-π, π].
float angle_difference(float a, float b) {
  constexpr float kTwoPi = 2 * std::numbers::pi_v<float>;
  float d = std::fmod(a - b, kTwoPi);
  if (d > std::numbers::pi_v<float>) d -= kTwoPi;
  if (d <= -std::numbers::pi_v<float>) d += kTwoPi;
  return d;
}

}  // namespace

void check_inputs(const WeaponsConfig& weapons, double step_s, Roster& roster,
                  const ViolationReport& report) {
  const float max_turn_rad = weapons.max_turn_rate_rad_s * static_cast<float>(step_s);
  for (Player& player : roster.players) {
    const PlayerInput& input = player.applied;
    if (input.sequence == 0 && !player.aimed) continue;  // no input yet: keep the spawn's aim
    if (!player.aimed || turn_rate_ok(player.aim_yaw_rad, player.aim_pitch_rad, input.yaw_rad,
                                      input.pitch_rad, max_turn_rad)) {
      player.aim_yaw_rad = input.yaw_rad;
      player.aim_pitch_rad = input.pitch_rad;
      player.aimed = true;
      continue;
    }
    // A snap faster than anyone turns (an aimbot, or a forged input): the aim follows at the
    // largest allowed turn, so a shot this step goes where a person could have aimed.
    note_violation(player, Violation::TurnRate, report);
    const float dyaw = angle_difference(input.yaw_rad, player.aim_yaw_rad);
    const float dpitch = input.pitch_rad - player.aim_pitch_rad;
    const float length = std::sqrt(dyaw * dyaw + dpitch * dpitch);
    const float scale = length > 0 ? max_turn_rad / length : 0.0f;
    player.aim_yaw_rad = angle_difference(player.aim_yaw_rad + dyaw * scale, 0.0f);
    player.aim_pitch_rad += dpitch * scale;
  }
}

void note_violation(Player& player, Violation violation, const ViolationReport& report) {
  const std::size_t index = static_cast<std::size_t>(violation);
  const std::uint64_t count = ++player.violations[index];
  ++report.counters.violations[index];
  // The first, then every power of two: a cheat is seen at once and cannot flood the log.
  if (report.log && (count & (count - 1)) == 0) {
    std::string line = "match ";
    line += std::to_string(report.match_id);
    line += ": account ";
    line += std::to_string(player.account);
    line += " (";
    line += player.name;
    line += "): ";
    line += server::name(violation);
    line += " violation, ";
    line += std::to_string(count);
    line += " so far";
    report.log(line);
  }
}

}  // namespace ricochet::server
