/// The phases of a match's step that take the inputs and move the players (match_movement.h).

#include "match_movement.h"

#include <cassert>

namespace ricochet::server {

void apply_inputs(Roster& roster, std::vector<RecordedInput>& step_inputs,
                  MatchCounters& counters) {
  step_inputs.clear();
  for (Player& player : roster.players) {
    if (!player.connected) continue;  // away: the neutral input disconnect() left
    bool repeated = false;
    player.applied = player.inputs.next(repeated);
    ++(repeated ? counters.inputs_repeated : counters.inputs_applied);
    step_inputs.push_back(RecordedInput{player.entity_id, player.applied,
                                        static_cast<std::uint32_t>(player.latency_us)});
  }
}

void move_players(const MovementConfig& movement, double step_s, Roster& roster,
                  physics::World& world) {
  const float dt_s = static_cast<float>(step_s);
  for (Player& player : roster.players) {
    if (!player.alive) continue;  // no body until the respawn
    const physics::BodyState state = world.body_state(player.body).value();
    player.grounded = is_grounded(world, player.body, state.radius, movement);
    const physics::Vec3 velocity =
        move_velocity(movement, player.applied, state.linear_velocity, player.grounded, dt_s);
    [[maybe_unused]] const physics::Status set = world.set_linear_velocity(player.body, velocity);
    assert(set.ok());  // validated inputs give finite velocities
  }
}

void step_physics(double step_s, physics::World& world, std::uint32_t& tick) {
  [[maybe_unused]] const physics::Status stepped = world.step(static_cast<physics::Real>(step_s));
  assert(stepped.ok());  // the step is 1/128..1/10 s
  ++tick;
}

}  // namespace ricochet::server
