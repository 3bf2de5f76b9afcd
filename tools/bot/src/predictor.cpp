/// Prediction and reconciliation of the own player (predictor.h).

#include "ricochet/bot/predictor.h"

#include <cassert>

#include "ricochet/proto/input_wire.h"

namespace ricochet::bot {

namespace {

physics::Vec3 to_physics(const Vec3& v) {
  return physics::Vec3(physics::Real(v[0]), physics::Real(v[1]), physics::Real(v[2]));
}

Vec3 to_view(const physics::Vec3& v) {
  return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
}

bool alive(const SeenEntity* own) {
  return own != nullptr && own->is_living_player();
}

}  // namespace

physics::CharacterIntent intent_of(const wire::Input& input) {
  const proto::Stick stick = proto::stick_of(input.move_right(), input.move_forward());
  return {physics::yaw_wish_direction(input.yaw(), stick.right, stick.forward),
          physics::stick_speed_fraction(stick.right, stick.forward),
          (input.buttons() & proto::kButtonJump) != 0};
}

Predictor::Predictor(PredictionWorld world, const proto::QuantizationSpec& spec, float tick_s)
    : world_(std::move(world)), spec_(spec), tick_s_(tick_s) {}

void Predictor::apply(const wire::Input& input) {
  if (!active_) return;
  step(input);
  predicted_.push_back({input.sequence(), world_.world.body_state(body_).value().position});
  while (predicted_.size() > 256) predicted_.pop_front();
}

void Predictor::step(const wire::Input& input) {
  const physics::BodyState state = world_.world.body_state(body_).value();
  const bool grounded = physics::is_grounded(world_.world, body_, state.radius, world_.motion);
  const physics::Vec3 velocity = physics::character_velocity(
      world_.motion, intent_of(input), state.linear_velocity, grounded, tick_s_);
  [[maybe_unused]] const physics::Status set = world_.world.set_linear_velocity(body_, velocity);
  assert(set.ok());  // validated rules and checked inputs give finite velocities
  [[maybe_unused]] const physics::Status stepped = world_.world.step(tick_s_);
  assert(stepped.ok());
}

void Predictor::seed(const SeenEntity& own) {
  const physics::Vec3 position = to_physics(own.position_m);
  if (body_.is_null()) {
    physics::BodyDef def = world_.player;
    def.position = position;
    body_ = world_.world.create_body(def).value();
  }
  [[maybe_unused]] const physics::Status moved =
      world_.world.set_transform(body_, position, physics::Quat::Identity());
  [[maybe_unused]] const physics::Status set =
      world_.world.set_linear_velocity(body_, to_physics(own.velocity_mps));
  assert(moved.ok() && set.ok());  // decoded snapshots are finite and within the bounds
}

void Predictor::reconcile(const SeenEntity* own, std::uint32_t acknowledged,
                          const std::deque<wire::Input>& unacknowledged) {
  if (own != nullptr) last_server_ = *own;
  if (!alive(own)) {
    active_ = false;
    predicted_.clear();
    return;
  }
  bool reset = !active_;
  if (active_) {
    const double moved = distance_m(own->position_m, seed_position_);
    if (moved <= kResetDistanceM) stats_.travelled_m += moved;
  }
  seed_position_ = own->position_m;
  if (!reset && acknowledged > measured_up_to_) {
    while (!predicted_.empty() && predicted_.front().sequence < acknowledged) {
      predicted_.pop_front();
    }
    if (!predicted_.empty() && predicted_.front().sequence == acknowledged) {
      // Compare on the snapshot's grid: what the server would have sent had it agreed.
      proto::EntityState state;
      state.position_m = to_view(predicted_.front().position);
      const proto::EntityState gridded = proto::dequantize(proto::quantize(state, spec_), spec_);
      const double error = distance_m(gridded.position_m, own->position_m);
      if (error > kResetDistanceM) {
        reset = true;
      } else {
        if (stats_.errors_m.size() < PredictionStats::kMaxSamples) stats_.errors_m.push_back(error);
        if (error > 0) ++stats_.corrections;
      }
    }
    measured_up_to_ = acknowledged;
  }
  if (reset) {
    ++stats_.resets;
    measured_up_to_ = acknowledged;
  }
  active_ = true;
  seed(*own);
  predicted_.clear();
  for (const wire::Input& input : unacknowledged) {
    if (input.sequence() <= acknowledged) continue;
    step(input);
    predicted_.push_back({input.sequence(), world_.world.body_state(body_).value().position});
    ++stats_.replayed;
  }
}

SeenEntity Predictor::own() const {
  if (!active_) return last_server_;
  const physics::BodyState state = world_.world.body_state(body_).value();
  SeenEntity out = last_server_;
  out.position_m = to_view(state.position);
  out.velocity_mps = to_view(state.linear_velocity);
  return out;
}

}  // namespace ricochet::bot
