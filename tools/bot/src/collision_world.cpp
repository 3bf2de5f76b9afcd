/// Checking and building a join reply's collision world (collision_world.h).

#include "ricochet/bot/collision_world.h"

#include <cmath>
#include <optional>

#include "ricochet/physics/scene_profile.h"

namespace ricochet::bot {

namespace {

using physics::Real;
using physics::Vec3;
using Limits = proto::CollisionWorldLimits;

constexpr const char* kAxes[] = {"x", "y", "z", "w"};

std::string out_of_range(const std::string& what, const std::string& range, float value) {
  return what + " must be " + range + ", got " + std::to_string(value);
}

/// The error of a repeated float field that must hold `count` values within +-limit.
template <class Field>
std::optional<std::string> check_floats(const Field& field, int count, float limit,
                                        const std::string& what) {
  if (field.size() != count) {
    return what + " must have " + std::to_string(count) + " values, got " +
           std::to_string(field.size());
  }
  for (int k = 0; k < count; ++k) {
    if (!std::isfinite(field[k]) || std::fabs(field[k]) > limit) {
      return out_of_range(what + "." + kAxes[k], "finite, within +-" + std::to_string(limit),
                          field[k]);
    }
  }
  return std::nullopt;
}

/// The error when a world has more than `limit` of something.
std::optional<std::string> too_many(int count, int limit, const char* what) {
  if (count <= limit) return std::nullopt;
  return "at most " + std::to_string(limit) + " " + what + ", got " + std::to_string(count);
}

Vec3 vec3(const google::protobuf::RepeatedField<float>& field, int at = 0) {
  return Vec3(Real(field[at]), Real(field[at + 1]), Real(field[at + 2]));
}

bool within(float value, float low, float high) {
  return std::isfinite(value) && value >= low && value <= high;
}

std::optional<std::string> check_motion(const wire::MovementRules& in,
                                        physics::CharacterMotionConfig& out) {
  out.max_speed_mps = in.max_speed_mps();
  out.ground_acceleration = in.ground_acceleration();
  out.air_acceleration = in.air_acceleration();
  out.friction = in.friction();
  out.stop_speed_mps = in.stop_speed_mps();
  out.jump_speed_mps = in.jump_speed_mps();
  out.ground_max_slope_deg = in.ground_max_slope_deg();
  out.ground_probe_m = in.ground_probe_m();
  if (std::string error = out.validate(); !error.empty()) return "movement " + error;
  return std::nullopt;
}

std::optional<std::string> add_planes(const wire::CollisionWorld& in, physics::World& world) {
  if (auto e = too_many(in.planes_size(), Limits::kMaxPlanes, "planes")) return e;
  for (int i = 0; i < in.planes_size(); ++i) {
    const wire::CollisionPlane& plane = in.planes(i);
    const std::string what = "plane " + std::to_string(i + 1);
    if (auto e = check_floats(plane.normal(), 3, 1e6f, what + " normal")) return e;
    if (!within(plane.offset_m(), -Limits::kMaxCoordinateM, Limits::kMaxCoordinateM)) {
      return out_of_range(what + " offset_m", "-100000..100000", plane.offset_m());
    }
    physics::PlaneDef def;
    def.normal = vec3(plane.normal());
    if (def.normal.norm() < Real(1e-3)) return what + " normal must not be zero";
    def.offset = Real(plane.offset_m());
    if (const auto added = world.add_plane(def); !added.ok()) {
      return what + ": " + added.error().message;
    }
  }
  return std::nullopt;
}

std::optional<std::string> add_boxes(const wire::CollisionWorld& in, physics::World& world) {
  if (auto e = too_many(in.boxes_size(), Limits::kMaxBoxes, "boxes")) return e;
  for (int i = 0; i < in.boxes_size(); ++i) {
    const wire::CollisionBox& box = in.boxes(i);
    const std::string what = "box " + std::to_string(i + 1);
    if (auto e = check_floats(box.center_m(), 3, Limits::kMaxCoordinateM, what + " center_m")) {
      return e;
    }
    if (auto e = check_floats(box.orientation(), 4, 1.01f, what + " orientation")) return e;
    if (auto e = check_floats(box.half_extents_m(), 3, Limits::kMaxCoordinateM,
                              what + " half_extents_m")) {
      return e;
    }
    physics::BoxDef def;
    def.center = vec3(box.center_m());
    def.orientation = physics::Quat(Real(box.orientation(3)), Real(box.orientation(0)),
                                    Real(box.orientation(1)), Real(box.orientation(2)));
    if (std::fabs(def.orientation.norm() - 1) > Real(1e-3)) {
      return out_of_range(what + " orientation length", "1 +- 0.001",
                          static_cast<float>(def.orientation.norm()));
    }
    def.orientation.normalize();
    def.half_extents = vec3(box.half_extents_m());
    for (int axis = 0; axis < 3; ++axis) {
      if (box.half_extents_m(axis) < 0.001f) {
        return out_of_range(what + " half_extents_m." + kAxes[axis], "0.001..100000",
                            box.half_extents_m(axis));
      }
    }
    if (const auto added = world.add_box(def); !added.ok()) {
      return what + ": " + added.error().message;
    }
  }
  return std::nullopt;
}

std::optional<std::string> add_meshes(const wire::CollisionWorld& in, physics::World& world) {
  if (auto e = too_many(in.meshes_size(), Limits::kMaxMeshes, "meshes")) return e;
  std::size_t vertices = 0;
  std::size_t triangles = 0;
  for (int i = 0; i < in.meshes_size(); ++i) {
    const wire::CollisionMesh& mesh = in.meshes(i);
    const std::string what = "mesh " + std::to_string(i + 1);
    const int floats = mesh.vertices_m_size();
    if (floats == 0 || floats % 3 != 0) {
      return what + " vertices_m must be a non-zero multiple of 3 floats, got " +
             std::to_string(floats);
    }
    if (mesh.indices_size() == 0 || mesh.indices_size() % 3 != 0) {
      return what + " indices must be a non-zero multiple of 3, got " +
             std::to_string(mesh.indices_size());
    }
    vertices += static_cast<std::size_t>(floats / 3);
    triangles += static_cast<std::size_t>(mesh.indices_size() / 3);
    if (vertices > Limits::kMaxVertices || triangles > Limits::kMaxTriangles) {
      return "at most " + std::to_string(Limits::kMaxVertices) + " vertices and " +
             std::to_string(Limits::kMaxTriangles) + " triangles in all meshes, " + what +
             " goes past that";
    }
    physics::MeshDef def;
    def.vertices.reserve(static_cast<std::size_t>(floats / 3));
    for (int v = 0; v < floats; v += 3) {
      for (int axis = 0; axis < 3; ++axis) {
        const float c = mesh.vertices_m(v + axis);
        if (!within(c, -Limits::kMaxCoordinateM, Limits::kMaxCoordinateM)) {
          return out_of_range(what + " vertex " + std::to_string(v / 3 + 1) + "." + kAxes[axis],
                              "-100000..100000", c);
        }
      }
      def.vertices.push_back(vec3(mesh.vertices_m(), v));
    }
    def.indices.assign(mesh.indices().begin(), mesh.indices().end());
    for (const std::uint32_t index : def.indices) {
      if (index >= def.vertices.size()) {
        return what + " index " + std::to_string(index) + " is not below its " +
               std::to_string(def.vertices.size()) + " vertices";
      }
    }
    if (const auto added = world.add_mesh(def); !added.ok()) {
      return what + ": " + added.error().message;
    }
  }
  return std::nullopt;
}

}  // namespace

std::variant<PredictionWorld, std::string> build_prediction_world(const wire::CollisionWorld& in) {
  physics::CharacterMotionConfig motion;
  if (!in.has_movement()) return std::string("movement rules missing");
  if (auto e = check_motion(in.movement(), motion)) return *e;
  if (!within(in.player_radius_m(), 0.05f, 5)) {
    return out_of_range("player_radius_m", "0.05..5", in.player_radius_m());
  }
  if (!within(in.player_mass_kg(), 1, 10000)) {
    return out_of_range("player_mass_kg", "1..10000", in.player_mass_kg());
  }
  if (auto e = check_floats(in.gravity_mps2(), 3, Limits::kMaxGravityMps2, "gravity_mps2")) {
    return *e;
  }
  physics::WorldDef def = physics::profiles::arena_players();
  def.enable_restitution = true;  // as the match's world (players have none: no bounce)
  def.gravity = vec3(in.gravity_mps2());
  if (def.gravity.norm() > Real(Limits::kMaxGravityMps2)) {
    return out_of_range("gravity_mps2 length", "0..100", static_cast<float>(def.gravity.norm()));
  }
  physics::Result<physics::World> created = physics::World::create(def);
  if (!created.ok()) return "world: " + created.error().message;
  PredictionWorld out{std::move(created).value(), physics::character_body_def(Vec3::Zero()),
                      motion};
  out.player.radius = Real(in.player_radius_m());
  out.player.mass = Real(in.player_mass_kg());
  if (auto e = add_planes(in, out.world)) return *e;
  if (auto e = add_boxes(in, out.world)) return *e;
  if (auto e = add_meshes(in, out.world)) return *e;
  return out;
}

}  // namespace ricochet::bot
