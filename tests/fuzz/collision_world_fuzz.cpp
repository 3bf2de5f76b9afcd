// libFuzzer target: the client's check and build of a join reply's collision world
// (tools/bot/include/ricochet/bot/collision_world.h) on arbitrary bytes, parsed as a
// wire::CollisionWorld. It must never crash, hang or leak; a world it accepts must be what it
// promises: within the limits, every number finite, and a player stepped in it for a second of
// movement stays finite.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <variant>

#include "ricochet/bot/collision_world.h"

namespace {

using ricochet::bot::PredictionWorld;
using ricochet::proto::CollisionWorldLimits;
namespace physics = ricochet::physics;

void require(bool condition) {
  if (!condition) __builtin_trap();
}

void check_accepted(const ricochet::wire::CollisionWorld& in, PredictionWorld& out) {
  require(in.planes_size() <= CollisionWorldLimits::kMaxPlanes);
  require(in.boxes_size() <= CollisionWorldLimits::kMaxBoxes);
  require(in.meshes_size() <= CollisionWorldLimits::kMaxMeshes);
  require(out.world.shape_count() ==
          static_cast<std::uint32_t>(in.planes_size() + in.boxes_size() + in.meshes_size()));
  require(out.motion.validate().empty());
  require(std::isfinite(out.player.radius) && out.player.radius > 0);
  require(out.world.definition().gravity.allFinite());
  // A second of running and jumping from above the origin: every state stays finite.
  physics::BodyDef def = out.player;
  def.position = physics::Vec3(0, 2, 0);
  const auto body = out.world.create_body(def);
  require(body.ok());
  const physics::CharacterIntent intent{physics::Vec3(1, 0, 0), 1, true};
  for (int k = 0; k < 60; ++k) {
    const physics::BodyState state = out.world.body_state(body.value()).value();
    const bool grounded = physics::is_grounded(out.world, body.value(), state.radius, out.motion);
    const physics::Vec3 v =
        physics::character_velocity(out.motion, intent, state.linear_velocity, grounded, 1.0f / 60);
    require(v.allFinite());
    require(out.world.set_linear_velocity(body.value(), v).ok());
    require(out.world.step(physics::Real(1.0 / 60)).ok());
  }
  require(out.world.body_state(body.value()).value().position.allFinite());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ricochet::wire::CollisionWorld in;
  if (!in.ParseFromArray(data, static_cast<int>(size))) return 0;
  auto built = ricochet::bot::build_prediction_world(in);
  if (auto* world = std::get_if<PredictionWorld>(&built)) {
    check_accepted(in, *world);
  } else {
    require(!std::get<std::string>(built).empty());
  }
  return 0;
}
