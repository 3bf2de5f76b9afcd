/// tests/vectors/movement_arena.txt and movement_foundry.txt: one player's movement in each
/// sample map the server ships (server/maps), tick by tick, as the authority computes it. Each
/// run is a lone player in the match's physics world (combat_world_def() with the map added by
/// add_map_to_world(), the body of player_body_def()) driven by a scripted input sequence:
/// running, turning, strafing, jumping, walking into walls, boxes and ramps, along mesh edges,
/// off ledges and into a pit. Every tick does what the match's tick does to a player
/// (match_movement.cpp): the wire input through validate_input(), is_grounded() before the
/// step, move_velocity() into set_linear_velocity(), then World::step of the tick, all through
/// the server's and the physics core's public headers with the default movement rules and
/// the default 60 Hz. A client predicting its player (PROTOCOL.md Movement rules and what one
/// physics step does to a predicting client's sphere) must reproduce every tick.
///   world map=NAME tick_hz=60 bytes=HEX
///     HEX: the wire::CollisionWorld a join reply of a match on this map carries (the same
///     shapes in the same order as the physics world; server::collision_world()).
///   run map=NAME name=NAME position=V
///     A new run: the player's sphere is created at rest at V, its spawn.
///   tick run=NAME t=N right=R forward=F yaw=F32 buttons=B grounded=G position=V velocity=V
///     Tick N (from 1) of the run: the wire Input's move_right R and move_forward F (steps of
///     1/127), yaw (F32: its IEEE bits, 4 bytes big-endian; one whose sine and cosine every
///     library rounds alike, portable_yaw()) and buttons B (bit 0 jump); G is 1
///     when is_grounded() held before the step (the ground the movement rules used), 0 when
///     not; the position (m) and velocity (m/s) after the step.
/// V is three floats x, y, z, each its IEEE bits as 4 bytes big-endian (24 hex digits).

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "ricochet/physics/world.h"
#include "ricochet/server/collision_world.h"
#include "ricochet/server/input_buffer.h"
#include "ricochet/server/map.h"
#include "ricochet/server/movement.h"
#include "ricochet/server/weapons.h"
#include "ricochet/wire/world.pb.h"
#include "vector_file.h"

namespace ricochet::vectors {
namespace {

constexpr int kTickRateHz = 60;

/// A stretch of the script: `ticks` inputs with one stick and buttons, the yaw turning by
/// `turn_deg_per_tick` from `yaw_deg` (degrees; 0 looks along -Z, -90 along +X).
struct Segment {
  int ticks = 0;
  int right = 0;
  int forward = 0;
  float yaw_deg = 0;
  float turn_deg_per_tick = 0;
  bool jump = false;
};

struct Run {
  const char* name;
  std::array<float, 3> start_m;
  std::vector<Segment> script;
};

struct MapRuns {
  const char* map;
  std::vector<Run> runs;
};

const std::vector<MapRuns>& scripts() {
  // Yaw: -90 runs along +X, 90 along -X, 180 along +Z, 0 along -Z. Strafing right looks along
  // the yaw and moves to its right.
  static const std::vector<MapRuns> kScripts = {
      {"arena",
       {
           // Settles from the spawn height onto the floor plane, runs up the ramp mesh across
           // its inner diagonal edge, over the platform box, off its far ledge, into the east
           // wall, then strafes along the wall and jumps against it.
           {"ramp_ledge_wall",
            {3, 0.45f, -6},
            {{10, 0, 0, -90},
             {175, 0, 127, -90},
             {40, 127, 127, -90},
             {30, 0, 127, -90, 0, true},
             {30, 0, 0, -90}}},
           // Up the ramp and off its open side edge (a mesh edge) onto the floor.
           {"ramp_side_edge",
            {4, 0.45f, -6.5f},
            {{50, 0, 127, -90}, {45, 0, 127, 180}, {25, -127, 0, 180}, {20, 0, 0, 180}}},
           // Into the rotated cover box (30 degrees), sliding along it, jumping at it, turning
           // while running around it.
           {"rotated_box",
            {-8, 0.45f, 4.5f},
            {{5, 0, 0, 180},
             {50, 0, 127, 180},
             {30, 90, 127, 180},
             {25, 0, 127, 180, 0, true},
             {90, 0, 127, 180, 4},
             {30, 0, 0, 180}}},
           // Grazing a box's vertical edge, into the corner of two outer walls, jumping in it,
           // then stopping by friction.
           {"box_edge_corner",
            {4.6f, 0.45f, 6.75f},
            {{60, 0, 127, -90}, {190, 0, 127, -18}, {30, 0, 127, -18, 0, true}, {40, 0, 0, -18}}},
       }},
      {"foundry",
       {
           // Up the east ramp (two triangles of an OBJ mesh) onto the balcony, along the thin
           // railing, onto the bridge, and off its side down to the ground.
           {"ramp_railing_bridge",
            {10, 0.45f, -27},
            {{10, 0, 0, -90},
             {150, 0, 127, -90},
             {225, 40, 127, 176},
             {20, 0, 127, 180},
             {60, 0, 127, 90},
             {25, -127, 0, 90},
             {60, 0, 0, 90}}},
           // Into the thin partition (0.15 m), jumping at it and strafing to its end.
           {"partition",
            {0, 0.45f, -24},
            {{60, 0, 127, 180}, {30, 0, 127, 180, 0, true}, {140, 127, 40, 180}, {20, 0, 0, 180}}},
           // Into the rotated crate (-20 degrees) and around it, turning.
           {"rotated_crate",
            {12, 0.45f, -14},
            {{45, 0, 127, -90}, {30, 0, 127, -90, 0, true}, {120, 0, 127, -90, 3}, {20, 0, 0, 0}}},
           // Off the ground slab's edge into the pit, running across it against the far wall.
           {"pit_edge", {0, 0.45f, -8}, {{40, 0, 127, 180}, {60, 30, 127, 180}, {20, 0, 0, 180}}},
       }},
  };
  return kScripts;
}

/// Whether `value` (a double sine or cosine) lies within a tenth of a float ulp of a float, so
/// that any single-precision sine or cosine with an error under 0.4 ulp gives that float.
bool far_from_rounding_boundary(double value) {
  const float nearest = static_cast<float>(value);
  const double ulp =
      static_cast<double>(std::nextafter(std::fabs(nearest), INFINITY)) - std::fabs(nearest);
  return std::fabs(value - nearest) <= 0.1 * ulp;
}

/// The float nearest to `yaw_rad` (a few ulps away at most) whose sine and cosine are far from a
/// float rounding boundary. glibc's sinf and cosf are not correctly rounded (about 1 % of yaws
/// in [0.001, 2 pi] give another float than the double sin rounded once, and glibc picks an FMA or
/// an SSE2 variant by CPU); on these yaws every C library and Java's Math agree, so the vectors
/// are the same on every machine and a client can match them bit for bit.
float portable_yaw(float yaw_rad) {
  float up = yaw_rad, down = yaw_rad;
  for (int k = 0; k < 4096; ++k) {
    for (const float yaw : {up, down}) {
      const double exact = yaw;
      if (far_from_rounding_boundary(std::sin(exact)) &&
          far_from_rounding_boundary(std::cos(exact)) &&
          std::sin(yaw) == static_cast<float>(std::sin(exact)) &&
          std::cos(yaw) == static_cast<float>(std::cos(exact))) {
        return yaw;
      }
    }
    up = std::nextafter(up, INFINITY);
    down = std::nextafter(down, -INFINITY);
  }
  throw std::runtime_error("movement vectors: no portable yaw near " + std::to_string(yaw_rad));
}

std::string float_hex(float value) {
  const auto bits = std::bit_cast<std::uint32_t>(value);
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string out(8, '0');
  for (int k = 0; k < 8; ++k)
    out[static_cast<std::size_t>(k)] = kDigits[(bits >> (28 - 4 * k)) & 15];
  return out;
}

std::string vector_hex(const physics::Vec3& v) {
  return float_hex(v.x()) + float_hex(v.y()) + float_hex(v.z());
}

server::Map load(const char* name) {
  const std::string path = std::string(RICOCHET_MAPS_DIR) + "/" + name + ".toml";
  server::MapResult loaded = server::load_map_file(path);
  if (const auto* error = std::get_if<server::MapError>(&loaded)) {
    throw std::runtime_error("movement vectors: " + error->describe());
  }
  return std::get<server::Map>(std::move(loaded));
}

/// The match's world for `map` with nothing but the map in it.
physics::World match_world(const server::Map& map) {
  physics::Result<physics::World> world = physics::World::create(server::combat_world_def());
  if (!world.ok()) throw std::runtime_error("movement vectors: " + world.error().message);
  if (const physics::Status added = server::add_map_to_world(map, world.value()); !added.ok()) {
    throw std::runtime_error("movement vectors: " + added.error().message);
  }
  return std::move(world).value();
}

void write_run(const server::Map& map, const Run& run, VectorFile& file) {
  const server::MovementConfig movement;
  const double step_s = 1.0 / kTickRateHz;
  const auto dt_s = static_cast<float>(step_s);
  physics::World world = match_world(map);
  const physics::Vec3 start(run.start_m[0], run.start_m[1], run.start_m[2]);
  const physics::BodyId body = world.create_body(server::player_body_def(start)).value();
  file.add(Record("run")
               .word("map", map.name)
               .word("name", run.name)
               .word("position", vector_hex(start)));
  std::uint32_t tick = 0;
  for (const Segment& segment : run.script) {
    for (int k = 0; k < segment.ticks; ++k) {
      ++tick;
      float yaw_deg = segment.yaw_deg + segment.turn_deg_per_tick * static_cast<float>(k);
      if (yaw_deg > 180) yaw_deg -= 360;  // the wire's yaw is within +-2 pi
      wire::Input in;
      in.set_sequence(tick);
      in.set_move_right(segment.right);
      in.set_move_forward(segment.forward);
      in.set_yaw(portable_yaw(yaw_deg * std::numbers::pi_v<float> / 180));
      in.set_buttons(segment.jump ? static_cast<std::uint32_t>(proto::kButtonJump) : 0u);
      server::PlayerInput input;
      server::InputDrop drop{};
      if (!server::validate_input(in, input, drop)) {
        throw std::runtime_error(std::string("movement vectors: input refused: ") + name(drop));
      }
      // The match's tick for one player (match_movement.cpp move_players, step_physics).
      const physics::BodyState state = world.body_state(body).value();
      const bool grounded = server::is_grounded(world, body, state.radius, movement);
      const physics::Vec3 velocity =
          server::move_velocity(movement, input, state.linear_velocity, grounded, dt_s);
      if (!world.set_linear_velocity(body, velocity).ok() ||
          !world.step(static_cast<physics::Real>(step_s)).ok()) {
        throw std::runtime_error("movement vectors: the step failed");
      }
      const physics::BodyState after = world.body_state(body).value();
      file.add(Record("tick")
                   .word("run", run.name)
                   .number("t", tick)
                   .number("right", in.move_right())
                   .number("forward", in.move_forward())
                   .word("yaw", float_hex(in.yaw()))
                   .number("buttons", in.buttons())
                   .number("grounded", grounded ? 1 : 0)
                   .word("position", vector_hex(after.position))
                   .word("velocity", vector_hex(after.linear_velocity)));
    }
  }
}

std::string write_movement(const char* map_name) {
  for (const MapRuns& runs : scripts()) {
    if (std::string(runs.map) != map_name) continue;
    const server::Map map = load(map_name);
    VectorFile file(std::string("movement_") + map_name,
                    "one player's movement, tick by tick, as the match computes it "
                    "(tools/vectors/movement_vectors.cpp)");
    file.add(
        Record("world")
            .word("map", map.name)
            .number("tick_hz", kTickRateHz)
            .bytes("bytes",
                   server::collision_world(map, server::MovementConfig{})->SerializeAsString()));
    for (const Run& run : runs.runs) write_run(map, run, file);
    return file.text();
  }
  throw std::runtime_error(std::string("movement vectors: no script for map ") + map_name);
}

}  // namespace

std::string write_movement_arena_vectors() {
  return write_movement("arena");
}

std::string write_movement_foundry_vectors() {
  return write_movement("foundry");
}

}  // namespace ricochet::vectors
