#include "snapshot_scenes.h"

#include <cmath>

#include "ricochet/physics/scene_profile.h"

namespace ricochet::bench {

namespace rp = ricochet::physics;
namespace proto = ricochet::proto;

namespace {

constexpr int kGrid = 30;
constexpr rp::Real kSmallRadius = 0.5;
constexpr rp::Real kLargeRadius = 2.5;  ///< m
constexpr rp::Real kDriveSpeed = 4;     ///< m/s, the large sphere's peak speed
const rp::Material kPropMaterial{.restitution = 0, .friction = 0.5f, .rolling_resistance = 0.1f};

constexpr rp::Real kArenaHalf = 20;  ///< m
constexpr rp::Real kRunSpeed = 6;    ///< m/s

}  // namespace

void read_entities(const SnapshotScene& scene, std::vector<proto::QuantizedEntity>& out) {
  const std::size_t n = scene.bodies.size();
  std::vector<rp::Vec3> positions(n), velocities(n);
  std::vector<rp::Quat> orientations(n);
  (void)scene.world.read_bodies(
      scene.bodies,
      {.positions = positions, .orientations = orientations, .linear_velocities = velocities});
  out.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    proto::EntityState state;
    state.id = static_cast<std::uint32_t>(i + 1);
    for (int a = 0; a < 3; ++a) {
      state.position_m[a] = static_cast<float>(positions[i][a]);
      state.velocity_mps[a] = static_cast<float>(velocities[i][a]);
    }
    state.orientation_xyzw = {
        static_cast<float>(orientations[i].x()), static_cast<float>(orientations[i].y()),
        static_cast<float>(orientations[i].z()), static_cast<float>(orientations[i].w())};
    out[i] = proto::quantize(state, scene.spec);
  }
}

SnapshotScene spheres_scene(const std::string& name, rp::Real spacing) {
  rp::WorldDef def = rp::profiles::physics_props();
  SnapshotScene scene{name, {}, rp::World::create(def).value(), {}, {}, {}, 1};
  scene.spec.bounds = {{-32.0f, -1.0f, -32.0f}, {32.0f, 15.0f, 32.0f}};
  // The floor resists rolling as the spheres do (a contact uses the geometric mean of both), so
  // a knocked sphere rolls a metre or two and rests, as Fiedler's cubes slide and stop.
  rp::PlaneDef floor;
  floor.material = kPropMaterial;
  (void)scene.world.add_plane(floor);
  for (int side = 0; side < 4; ++side) {  // walls inside the snapshot bounds
    const rp::Real sign = side % 2 == 0 ? 1 : -1;
    rp::PlaneDef wall;
    wall.normal = side < 2 ? rp::Vec3(sign, 0, 0) : rp::Vec3(0, 0, sign);
    wall.offset = -31;
    wall.material = kPropMaterial;
    (void)scene.world.add_plane(wall);
  }
  const rp::Real half = (kGrid - 1) * spacing / 2;
  for (int x = 0; x < kGrid; ++x) {
    for (int z = 0; z < kGrid; ++z) {
      rp::BodyDef body;
      body.position = rp::Vec3(x * spacing - half, kSmallRadius, z * spacing - half);
      body.radius = kSmallRadius;
      body.material = kPropMaterial;
      scene.bodies.push_back(scene.world.create_body(body).value());
    }
  }
  rp::BodyDef large;
  large.type = rp::BodyType::Kinematic;
  large.radius = kLargeRadius;
  large.position = rp::Vec3(-half - 6, kLargeRadius, 0);
  scene.bodies.push_back(scene.world.create_body(large).value());
  // A figure of eight through the pile, starting from the parked position's side.
  scene.drive = [half](SnapshotScene& s, int step, bool moving) {
    const rp::BodyId ball = s.bodies.back();
    if (!moving) {
      (void)s.world.set_linear_velocity(ball, rp::Vec3::Zero());
      (void)s.world.set_angular_velocity(ball, rp::Vec3::Zero());
      return;
    }
    const rp::Real t = static_cast<rp::Real>(step) / 60;
    const rp::Real reach = half + 6;
    const rp::Real w = kDriveSpeed / reach;
    const rp::Vec3 target(-reach * std::cos(w * t), kLargeRadius,
                          (reach / 2) * std::sin(2 * w * t));
    const rp::Vec3 now = s.world.body_state(ball).value().position;
    const rp::Vec3 velocity = (target - now) * 60;
    (void)s.world.set_linear_velocity(ball, velocity);
    // Rolling: spin about the horizontal axis across the motion.
    (void)s.world.set_angular_velocity(ball, rp::Vec3::UnitY().cross(velocity) / -kLargeRadius);
  };
  scene.viewer = [](const SnapshotScene& s, int) {
    const rp::Vec3 p = s.world.body_state(s.bodies.back()).value().position;
    return std::array<float, 3>{static_cast<float>(p.x()), static_cast<float>(p.y()),
                                static_cast<float>(p.z())};
  };
  return scene;
}

SnapshotScene players_scene(int players) {
  SnapshotScene scene{"players" + std::to_string(players),
                      {},
                      rp::World::create(rp::profiles::arena_players()).value(),
                      {},
                      {},
                      {},
                      players};
  scene.spec.bounds = {{-24.0f, -2.0f, -24.0f}, {24.0f, 14.0f, 24.0f}};
  (void)scene.world.add_plane({.normal = rp::Vec3::UnitY(), .offset = 0});
  for (int side = 0; side < 4; ++side) {
    const rp::Real sign = side % 2 == 0 ? 1 : -1;
    const rp::Vec3 normal = side < 2 ? rp::Vec3(sign, 0, 0) : rp::Vec3(0, 0, sign);
    (void)scene.world.add_plane({.normal = normal, .offset = -kArenaHalf});
  }
  for (int i = 0; i < players; ++i) {
    const rp::Real angle = 2 * 3.14159265358979 * i / players;
    const rp::Real radius = 4 + 12 * ((i * 7919) % 13) / 13.0;
    scene.bodies.push_back(scene.world
                               .create_body(rp::profiles::player(rp::Vec3(
                                   radius * std::cos(angle), 0.4, radius * std::sin(angle))))
                               .value());
  }
  // Each player runs on a heading that turns slowly, and jumps now and then.
  scene.drive = [](SnapshotScene& s, int step, bool moving) {
    for (std::size_t i = 0; i < s.bodies.size(); ++i) {
      const rp::BodyState state = s.world.body_state(s.bodies[i]).value();
      rp::Vec3 velocity = rp::Vec3::Zero();
      if (moving) {
        const rp::Real t = static_cast<rp::Real>(step) / 60;
        const rp::Real heading = 1.7 * static_cast<rp::Real>(i) + 0.6 * t +
                                 std::sin(0.37 * t + static_cast<rp::Real>(i));
        velocity = rp::Vec3(std::cos(heading), 0, std::sin(heading)) * kRunSpeed;
        // Turn back towards the centre near the walls.
        if (std::abs(state.position.x()) > kArenaHalf - 3) velocity.x() = -state.position.x();
        if (std::abs(state.position.z()) > kArenaHalf - 3) velocity.z() = -state.position.z();
      }
      const bool on_ground = state.position.y() < 0.41;
      const bool jump = moving && on_ground && (step + 37 * static_cast<int>(i)) % 150 == 0;
      velocity.y() = jump ? 5 : state.linear_velocity.y();
      (void)s.world.set_linear_velocity(s.bodies[i], velocity);
    }
  };
  scene.viewer = [](const SnapshotScene& s, int client) {
    const rp::Vec3 p = s.world.body_state(s.bodies[client]).value().position;
    return std::array<float, 3>{static_cast<float>(p.x()), static_cast<float>(p.y()),
                                static_cast<float>(p.z())};
  };
  return scene;
}

}  // namespace ricochet::bench
