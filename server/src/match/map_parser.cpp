/// The map text format's parser (map.h): one statement a line, validated as it is read.

#include <charconv>
#include <cmath>
#include <fstream>
#include <numbers>
#include <system_error>

#include "ricochet/server/map.h"

namespace ricochet::server {

namespace {

using physics::Vec3;

constexpr std::size_t kMaxLineChars = 512;
constexpr std::size_t kMaxBoxes = 1024;
constexpr std::size_t kMaxMeshes = 64;
constexpr std::size_t kMaxMeshVertices = 65536;
constexpr std::size_t kMaxMeshTriangles = 65536;
constexpr std::size_t kMaxSpawns = 64;
constexpr std::size_t kMaxNameChars = 32;
constexpr double kMaxCoordinate = 100000;
/// Smallest half extent of a box, m. Anything thinner means nothing to a 0.4 m player, and a
/// positive double below float's range would become a zero-sized box in the world (found by
/// map_parser_fuzz).
constexpr double kMinSize = 0.001;
constexpr double kRadiansPerDegree = std::numbers::pi / 180;

/// Thrown inside the parser only, caught in parse_map: the first error ends the parse.
struct ParseFailure {
  MapError error;
};

bool is_name(std::string_view text) {
  if (text.empty() || text.size() > kMaxNameChars) return false;
  for (const char c : text) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '-';
    if (!ok) return false;
  }
  return true;
}

/// Quotes a token for an error message, cut to a readable length and printable.
std::string quoted(std::string_view token) {
  std::string out = "'";
  for (const char c : token.substr(0, 40)) {
    out += (c >= 0x20 && c < 0x7f) ? c : '?';
  }
  if (token.size() > 40) out += "...";
  return out + "'";
}

class Parser {
 public:
  explicit Parser(std::string_view text) : text_(text) {}

  Map parse() {
    if (text_.size() > kMaxMapBytes) {
      fail(0, "map",
           "expected at most " + std::to_string(kMaxMapBytes) + " bytes, got " +
               std::to_string(text_.size()));
    }
    while (next_line()) statement();
    if (!seen_version_) fail(0, "ricochet-map", "expected the version line 'ricochet-map 1'");
    if (mesh_open_) fail(line_, "end", "expected 'end' to close mesh " + map_.meshes.back().name);
    if (map_.name.empty()) fail(0, "name", "expected a 'name' line");
    if (!seen_bounds_) fail(0, "bounds", "expected a 'bounds' line");
    if (map_.spawns.empty()) fail(0, "spawn", "expected at least one 'spawn' line");
    return std::move(map_);
  }

 private:
  [[noreturn]] void fail(int line, std::string field, std::string message) const {
    throw ParseFailure{MapError{line, std::move(field), std::move(message)}};
  }
  [[noreturn]] void fail(std::string field, std::string message) const {
    fail(line_, std::move(field), std::move(message));
  }

  /// Splits the next non-blank line into tokens_; false at the end of the text.
  bool next_line() {
    while (position_ < text_.size()) {
      const std::size_t end = std::min(text_.find('\n', position_), text_.size());
      std::string_view line = text_.substr(position_, end - position_);
      position_ = end + 1;
      ++line_;
      if (line.size() > kMaxLineChars) {
        fail("line", "expected at most " + std::to_string(kMaxLineChars) + " characters, got " +
                         std::to_string(line.size()));
      }
      line = line.substr(0, line.find('#'));
      tokens_.clear();
      std::size_t at = 0;
      while (at < line.size()) {
        const std::size_t start = line.find_first_not_of(" \t\r", at);
        if (start == std::string_view::npos) break;
        const std::size_t stop = std::min(line.find_first_of(" \t\r", start), line.size());
        tokens_.push_back(line.substr(start, stop - start));
        at = stop;
      }
      if (!tokens_.empty()) return true;
    }
    return false;
  }

  void expect_tokens(std::size_t low, std::size_t high, const char* usage) const {
    const std::size_t arguments = tokens_.size() - 1;
    if (arguments < low || arguments > high) {
      fail(std::string(tokens_[0]),
           "expected '" + std::string(usage) + "', got " + std::to_string(arguments) + " values");
    }
  }

  double number(std::size_t index, const std::string& field, double low, double high,
                bool low_open = false) const {
    const std::string_view token = tokens_[index];
    double value = 0;
    const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (error != std::errc{} || end != token.data() + token.size() || !std::isfinite(value)) {
      fail(field, "expected a decimal number, got " + quoted(token));
    }
    if (value < low || value > high || (low_open && value == low)) {
      fail(field, std::string("expected a number ") + (low_open ? "> " : ">= ") +
                      std::to_string(low) + " and <= " + std::to_string(high) + ", got " +
                      quoted(token));
    }
    return value;
  }
  double coordinate(std::size_t index, const std::string& field) const {
    return number(index, field, -kMaxCoordinate, kMaxCoordinate);
  }
  Vec3 point(std::size_t index, const std::string& field) const {
    return Vec3(coordinate(index, field + ".x"), coordinate(index + 1, field + ".y"),
                coordinate(index + 2, field + ".z"));
  }
  void require_inside(const Vec3& p, const std::string& field) const {
    if (!seen_bounds_) fail(field, "expected 'bounds' before any geometry");
    if (!map_.contains(p)) {
      fail(field, "expected a point inside the bounds, got (" + std::to_string(p.x()) + ", " +
                      std::to_string(p.y()) + ", " + std::to_string(p.z()) + ")");
    }
  }

  void statement() {
    const std::string_view keyword = tokens_[0];
    if (!seen_version_) {
      if (keyword != "ricochet-map") {
        fail("ricochet-map",
             "expected the version line 'ricochet-map 1' first, got " + quoted(keyword));
      }
      expect_tokens(1, 1, "ricochet-map VERSION");
      if (tokens_[1] != "1") fail("ricochet-map version", "expected 1, got " + quoted(tokens_[1]));
      seen_version_ = true;
      return;
    }
    if (mesh_open_) return mesh_statement(keyword);
    if (keyword == "name") return name_statement();
    if (keyword == "bounds") return bounds_statement();
    if (keyword == "floor") return floor_statement();
    if (keyword == "box") return box_statement();
    if (keyword == "wall") return wall_statement();
    if (keyword == "mesh") return mesh_start();
    if (keyword == "spawn") return spawn_statement();
    fail("statement",
         "expected one of name, bounds, floor, box, wall, mesh, spawn, got " + quoted(keyword));
  }

  void name_statement() {
    expect_tokens(1, 1, "name NAME");
    if (!map_.name.empty()) fail("name", "expected one 'name' line, got a second");
    if (!is_name(tokens_[1])) {
      fail("name", "expected 1..32 of A-Z a-z 0-9 _ -, got " + quoted(tokens_[1]));
    }
    map_.name = std::string(tokens_[1]);
  }

  void bounds_statement() {
    expect_tokens(6, 6, "bounds MINX MINY MINZ MAXX MAXY MAXZ");
    if (seen_bounds_) fail("bounds", "expected one 'bounds' line, got a second");
    map_.bounds_min_m = point(1, "bounds min");
    map_.bounds_max_m = point(4, "bounds max");
    static const char* const kAxes[] = {"x", "y", "z"};
    for (int axis = 0; axis < 3; ++axis) {
      if (!(map_.bounds_max_m[axis] > map_.bounds_min_m[axis])) {
        fail(std::string("bounds max.") + kAxes[axis],
             "expected more than min." + std::string(kAxes[axis]) + " " +
                 std::to_string(map_.bounds_min_m[axis]) + ", got " +
                 std::to_string(map_.bounds_max_m[axis]));
      }
    }
    seen_bounds_ = true;
  }

  void floor_statement() {
    expect_tokens(1, 1, "floor Y");
    if (map_.floor_y_m) fail("floor", "expected one 'floor' line, got a second");
    const double y = coordinate(1, "floor y");
    require_inside(Vec3(map_.bounds_min_m.x(), y, map_.bounds_min_m.z()), "floor y");
    map_.floor_y_m = static_cast<float>(y);
  }

  void add_box(const MapBox& box) {
    if (map_.boxes.size() >= kMaxBoxes) {
      fail(std::string(tokens_[0]),
           "expected at most " + std::to_string(kMaxBoxes) + " boxes and walls, got more");
    }
    map_.boxes.push_back(box);
  }

  void box_statement() {
    expect_tokens(6, 7, "box CX CY CZ HX HY HZ [YAW]");
    MapBox box;
    box.center_m = point(1, "box center");
    require_inside(box.center_m, "box center");
    box.half_extents_m = Vec3(number(4, "box half_extents.x", kMinSize, kMaxCoordinate),
                              number(5, "box half_extents.y", kMinSize, kMaxCoordinate),
                              number(6, "box half_extents.z", kMinSize, kMaxCoordinate));
    if (tokens_.size() == 8) {
      box.yaw_rad = static_cast<float>(number(7, "box yaw", -360, 360) * kRadiansPerDegree);
    }
    add_box(box);
  }

  void wall_statement() {
    expect_tokens(7, 7, "wall X0 Z0 X1 Z1 BASE HEIGHT THICKNESS");
    const double x0 = coordinate(1, "wall x0");
    const double z0 = coordinate(2, "wall z0");
    const double x1 = coordinate(3, "wall x1");
    const double z1 = coordinate(4, "wall z1");
    const double base = coordinate(5, "wall base");
    const double height = number(6, "wall height", 2 * kMinSize, kMaxCoordinate);
    const double thickness = number(7, "wall thickness", 2 * kMinSize, kMaxCoordinate);
    const double length = std::hypot(x1 - x0, z1 - z0);
    if (!(length >= 2 * kMinSize)) {
      fail("wall x1", "expected an end point at least " + std::to_string(2 * kMinSize) +
                          " m from the start point, got " + std::to_string(length));
    }
    MapBox box;
    box.center_m = Vec3((x0 + x1) / 2, base + height / 2, (z0 + z1) / 2);
    require_inside(box.center_m, "wall center");
    box.half_extents_m = Vec3(length / 2, height / 2, thickness / 2);
    // The box's local +X runs along the wall; yaw turns +X towards -Z.
    box.yaw_rad = static_cast<float>(std::atan2(-(z1 - z0), x1 - x0));
    add_box(box);
  }

  void mesh_start() {
    expect_tokens(1, 1, "mesh NAME");
    if (!seen_bounds_) fail("mesh", "expected 'bounds' before any geometry");
    if (map_.meshes.size() >= kMaxMeshes) {
      fail("mesh", "expected at most " + std::to_string(kMaxMeshes) + " meshes, got more");
    }
    if (!is_name(tokens_[1])) {
      fail("mesh name", "expected 1..32 of A-Z a-z 0-9 _ -, got " + quoted(tokens_[1]));
    }
    map_.meshes.push_back(MapMesh{std::string(tokens_[1]), {}, {}});
    mesh_open_ = true;
  }

  void mesh_statement(std::string_view keyword) {
    MapMesh& mesh = map_.meshes.back();
    if (keyword == "vertex") {
      expect_tokens(3, 3, "vertex X Y Z");
      if (mesh.vertices_m.size() >= kMaxMeshVertices) {
        fail("vertex", "expected at most " + std::to_string(kMaxMeshVertices) +
                           " vertices in mesh " + mesh.name + ", got more");
      }
      const Vec3 vertex = point(1, "vertex");
      require_inside(vertex, "vertex");
      mesh.vertices_m.push_back(vertex);
    } else if (keyword == "triangle") {
      expect_tokens(3, 3, "triangle A B C");
      if (mesh.indices.size() / 3 >= kMaxMeshTriangles) {
        fail("triangle", "expected at most " + std::to_string(kMaxMeshTriangles) +
                             " triangles in mesh " + mesh.name + ", got more");
      }
      std::uint32_t corner[3];
      static const char* const kCorners[] = {"triangle a", "triangle b", "triangle c"};
      for (int k = 0; k < 3; ++k) {
        const std::string_view token = tokens_[1 + k];
        std::uint32_t index = 0;
        const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), index);
        if (error != std::errc{} || end != token.data() + token.size() ||
            index >= mesh.vertices_m.size()) {
          fail(kCorners[k], mesh.vertices_m.empty()
                                ? "expected 'vertex' lines before the first triangle of mesh " +
                                      mesh.name + ", got none"
                                : "expected a vertex number 0.." +
                                      std::to_string(mesh.vertices_m.size() - 1) + " of mesh " +
                                      mesh.name + ", got " + quoted(token));
        }
        corner[k] = index;
      }
      const Vec3& a = mesh.vertices_m[corner[0]];
      const Vec3 normal = (mesh.vertices_m[corner[1]] - a).cross(mesh.vertices_m[corner[2]] - a);
      if (!(normal.norm() > physics::Real(1e-6))) {
        fail("triangle",
             "expected three distinct corners enclosing an area, got a degenerate "
             "triangle");
      }
      mesh.indices.insert(mesh.indices.end(), corner, corner + 3);
    } else if (keyword == "end") {
      expect_tokens(0, 0, "end");
      if (mesh.indices.empty()) {
        fail("end", "expected at least one triangle in mesh " + mesh.name + ", got none");
      }
      mesh_open_ = false;
    } else {
      fail("mesh " + mesh.name, "expected vertex, triangle or end, got " + quoted(keyword));
    }
  }

  void spawn_statement() {
    expect_tokens(4, 4, "spawn X Y Z YAW");
    if (map_.spawns.size() >= kMaxSpawns) {
      fail("spawn", "expected at most " + std::to_string(kMaxSpawns) + " spawns, got more");
    }
    MapSpawn spawn;
    spawn.position_m = point(1, "spawn position");
    require_inside(spawn.position_m, "spawn position");
    spawn.yaw_rad = static_cast<float>(number(4, "spawn yaw", -360, 360) * kRadiansPerDegree);
    map_.spawns.push_back(spawn);
  }

  std::string_view text_;
  std::size_t position_ = 0;
  int line_ = 0;
  std::vector<std::string_view> tokens_;
  Map map_;
  bool seen_version_ = false;
  bool seen_bounds_ = false;
  bool mesh_open_ = false;
};

}  // namespace

bool Map::contains(const Vec3& point_m) const {
  return (point_m.array() >= bounds_min_m.array()).all() &&
         (point_m.array() <= bounds_max_m.array()).all();
}

std::string MapError::describe() const {
  return (line > 0 ? "line " + std::to_string(line) + ": " : std::string()) + field + ": " +
         message;
}

MapResult parse_map(std::string_view text) {
  try {
    return Parser(text).parse();
  } catch (const ParseFailure& failure) {
    return failure.error;
  }
}

MapResult load_map_file(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return MapError{0, "file", "expected a readable map file at " + path};
  std::string text;
  text.resize(kMaxMapBytes + 1);
  file.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(file.gcount()));
  if (file.bad()) return MapError{0, "file", "could not read " + path};
  return parse_map(text);
}

}  // namespace ricochet::server
