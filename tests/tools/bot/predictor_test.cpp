// Prediction and reconciliation (predictor.h) against a scripted server: a second physics world
// built from the same collision world, stepping the same inputs, whose snapshots are fed to the
// predictor by hand a few ticks late. With the same inputs the error is exactly 0; after an
// injected push it shows once and the prediction converges; deaths and respawns are resets.
#include "ricochet/bot/predictor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <deque>

#include "collision_world_fixture.h"
#include "ricochet/bot/input_history.h"

namespace ricochet::bot::predictor_test {
namespace {

constexpr float kTickS = 1.0f / 60;

PredictionWorld world() {
  return std::get<PredictionWorld>(build_prediction_world(testing::arena_world()));
}

/// The bot's inputs: run and turn, strafe now and then, jump every second.
wire::Input scripted_input(int k) {
  wire::Input input;
  input.set_move_forward(127);
  input.set_move_right(k % 90 < 30 ? 127 : (k % 90 < 45 ? -60 : 0));
  input.set_yaw(0.6f * std::sin(0.02f * float(k)));
  input.set_buttons(k % 60 == 30 ? 1u : 0u);
  return input;
}

/// The authority: the same rules in its own world; its state is what it sends (it keeps the
/// quantised state it sends, as a server whose state lives on the snapshot grid).
class ScriptedServer {
 public:
  ScriptedServer() : world_(world()) {
    physics::BodyDef def = world_.player;
    def.position = physics::Vec3(0, physics::Real(0.4), 0);
    body_ = world_.world.create_body(def).value();
  }
  void apply(const wire::Input& input) {
    const physics::BodyState state = world_.world.body_state(body_).value();
    const bool grounded = physics::is_grounded(world_.world, body_, state.radius, world_.motion);
    ASSERT_TRUE(world_.world
                    .set_linear_velocity(
                        body_, physics::character_velocity(world_.motion, intent_of(input),
                                                           state.linear_velocity, grounded, kTickS))
                    .ok());
    ASSERT_TRUE(world_.world.step(kTickS).ok());
  }
  /// Its player as a decoded snapshot shows it; the body keeps exactly that state.
  SeenEntity snapshot() {
    const physics::BodyState state = world_.world.body_state(body_).value();
    proto::EntityState sent;
    sent.id = 1;
    for (int a = 0; a < 3; ++a) {
      sent.position_m[a] = static_cast<float>(state.position[a]);
      sent.velocity_mps[a] = static_cast<float>(state.linear_velocity[a]);
    }
    const proto::EntityState seen = proto::dequantize(proto::quantize(sent, spec_), spec_);
    const physics::Vec3 p(seen.position_m[0], seen.position_m[1], seen.position_m[2]);
    const physics::Vec3 v(seen.velocity_mps[0], seen.velocity_mps[1], seen.velocity_mps[2]);
    EXPECT_TRUE(world_.world.set_transform(body_, p, physics::Quat::Identity()).ok());
    EXPECT_TRUE(world_.world.set_linear_velocity(body_, v).ok());
    return {1, seen.position_m, seen.velocity_mps, 0};
  }
  /// Moves its player by `offset` (a knockback the bot could not foresee).
  void shift(const physics::Vec3& offset) {
    const physics::Vec3 p = world_.world.body_state(body_).value().position;
    ASSERT_TRUE(world_.world.set_transform(body_, p + offset, physics::Quat::Identity()).ok());
  }
  const proto::QuantizationSpec& spec() const { return spec_; }

 private:
  PredictionWorld world_;
  physics::BodyId body_;
  proto::QuantizationSpec spec_;
};

/// The bot's side: history and predictor. Each tick the bot sends input k, the server applies
/// it at once, and the snapshot after it arrives `delay` ticks later.
struct Link {
  ScriptedServer server;
  Predictor predictor{world(), server.spec(), kTickS};
  InputHistory history;
  struct InFlight {
    int arrives = 0;
    SeenEntity own;
    std::uint32_t ack = 0;
  };
  std::deque<InFlight> in_flight;

  void run(int from, int to, int delay, int shift_at = -1) {
    for (int k = from; k < to; ++k) {
      const wire::Input& input = history.push(scripted_input(k));
      predictor.apply(input);
      server.apply(input);
      if (k == shift_at) server.shift(physics::Vec3(0.5, 0, 0));
      in_flight.push_back({k + delay, server.snapshot(), input.sequence()});
      while (!in_flight.empty() && in_flight.front().arrives <= k) {
        history.acknowledge(in_flight.front().ack);
        predictor.reconcile(&in_flight.front().own, in_flight.front().ack,
                            history.unacknowledged());
        in_flight.pop_front();
      }
    }
  }
};

TEST(Predictor, WithTheSameInputsTheErrorIsExactlyZero) {
  Link link;
  link.run(0, 400, /*delay=*/12);
  const PredictionStats& stats = link.predictor.stats();
  ASSERT_GT(stats.errors_m.size(), 350u);
  for (std::size_t i = 0; i < stats.errors_m.size(); ++i) {
    ASSERT_EQ(stats.errors_m[i], 0.0) << "acknowledgement " << i;
  }
  EXPECT_EQ(stats.corrections, 0u);
  EXPECT_EQ(stats.resets, 1u);  // the first snapshot seeds it
  EXPECT_GT(stats.replayed, 350u * 10);
  // And it went somewhere: the prediction is not trivially still.
  const SeenEntity own = link.predictor.own();
  EXPECT_GT(std::hypot(own.position_m[0], own.position_m[2]), 20.0f);
}

TEST(Predictor, ConvergesAfterAnInjectedDiscrepancy) {
  Link link;
  link.run(0, 200, /*delay=*/8, /*shift_at=*/120);
  const std::vector<double>& errors = link.predictor.stats().errors_m;
  // Sample i is input i + 1's acknowledgement (input 0's seeded the prediction). Input 120's
  // shows the 0.5 m the server moved its player by; every input after it was predicted (or
  // replayed) from the corrected state when its acknowledgement came: exactly 0 again.
  ASSERT_EQ(errors.size(), 191u);
  for (std::size_t i = 0; i < errors.size(); ++i) {
    if (i + 1 == 120) {
      EXPECT_NEAR(errors[i], 0.5, 0.002);
    } else {
      EXPECT_EQ(errors[i], 0.0) << "input " << i + 1;
    }
  }
  EXPECT_EQ(link.predictor.stats().corrections, 1u);
}

TEST(Predictor, DeathAndRespawnAreResetsNotErrors) {
  Predictor predictor(world(), proto::QuantizationSpec{}, kTickS);
  InputHistory history;
  SeenEntity own{1, {0, 0.4f, 0}, {0, 0, 0}, 0};
  predictor.reconcile(&own, 0, history.unacknowledged());
  EXPECT_TRUE(predictor.active());
  for (int k = 0; k < 10; ++k) predictor.apply(history.push(scripted_input(k)));
  SeenEntity dead = own;
  dead.flags = proto::kEntityDead;
  history.acknowledge(5);
  predictor.reconcile(&dead, 5, history.unacknowledged());
  EXPECT_FALSE(predictor.active());
  predictor.apply(history.push(scripted_input(10)));  // idle: nothing moves
  EXPECT_EQ(predictor.own().position_m, dead.position_m);
  SeenEntity respawned{1, {20, 0.4f, 20}, {0, 0, 0}, 0};
  history.acknowledge(11);
  predictor.reconcile(&respawned, 11, history.unacknowledged());
  EXPECT_TRUE(predictor.active());
  EXPECT_EQ(predictor.stats().resets, 2u);
  EXPECT_TRUE(predictor.stats().errors_m.empty());
  // A jump of more than kResetDistanceM while alive (a teleport) is a reset as well.
  predictor.apply(history.push(scripted_input(11)));
  SeenEntity teleported{1, {-20, 0.4f, -20}, {0, 0, 0}, 0};
  history.acknowledge(12);
  predictor.reconcile(&teleported, 12, history.unacknowledged());
  EXPECT_EQ(predictor.stats().resets, 3u);
  EXPECT_TRUE(predictor.stats().errors_m.empty());
}

TEST(Predictor, TheInputConversionIsTheServers) {
  wire::Input diagonal;
  diagonal.set_move_right(127);
  diagonal.set_move_forward(127);
  const physics::CharacterIntent intent = intent_of(diagonal);
  EXPECT_FLOAT_EQ(intent.wish_speed_fraction, 1.0f);  // shortened to length 1, not 1.41
  EXPECT_TRUE(intent.wish_direction.isApprox(physics::Vec3(1, 0, -1).normalized(), 1e-6f));
  wire::Input half;
  half.set_move_forward(-64);
  half.set_buttons(1);
  EXPECT_NEAR(intent_of(half).wish_speed_fraction, 64.0f / 127, 1e-7);
  EXPECT_TRUE(intent_of(half).jump);
  EXPECT_TRUE(intent_of(half).wish_direction.isApprox(physics::Vec3(0, 0, 1), 1e-6f));
}

}  // namespace
}  // namespace ricochet::bot::predictor_test
