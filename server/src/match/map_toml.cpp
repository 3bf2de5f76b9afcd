/// The TOML map format's parser (map.h parse_map): reads the document with toml++, then checks
/// every table and key against server/maps/FORMAT.md, in a fixed order so that later checks may
/// use earlier results (the bounds before anything placed inside them).

#include <toml++/toml.h>

#include <charconv>
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "map_text.h"
#include "ricochet/server/map.h"
#include "ricochet/wire/game.pb.h"

namespace ricochet::server {

static_assert(static_cast<int>(Team::Red) == wire::TEAM_RED);
static_assert(static_cast<int>(Team::Blue) == wire::TEAM_BLUE);
static_assert(static_cast<int>(PickupKind::Health) == wire::PICKUP_KIND_HEALTH);
static_assert(static_cast<int>(PickupKind::Armor) == wire::PICKUP_KIND_ARMOR);
static_assert(static_cast<int>(PickupKind::Ammo) == wire::PICKUP_KIND_AMMO);

namespace {

using physics::Vec3;

constexpr std::int64_t kFormatVersion = 1;
constexpr std::size_t kMaxBoxes = 1024;  ///< boxes and walls together
constexpr std::size_t kMaxMeshes = 64;
constexpr std::size_t kMaxObjFiles = 16;
constexpr std::size_t kMaxMeshVertices = 65536;
constexpr std::size_t kMaxMeshTriangles = 65536;
constexpr std::size_t kMaxSpawns = 64;
constexpr std::size_t kMaxPickups = 128;
constexpr std::size_t kMaxKillVolumes = 64;
constexpr std::size_t kMaxNameChars = 32;
constexpr std::size_t kMaxPathChars = 128;
constexpr double kMaxCoordinate = 100000;
/// Smallest half extent of a box, m. Anything thinner means nothing to a 0.4 m player, and a
/// positive double below float's range would become a zero-sized box in the world.
constexpr double kMinSize = 0.001;
/// Smallest span of the bounds per axis, m; keeps min < max after the cast to float.
constexpr double kMinBoundsSpan = 1;
/// Smallest span of a kill volume per axis, m; more than float's spacing at 100000 m.
constexpr double kMinKillSpan = 0.1;
constexpr double kRadiansPerDegree = std::numbers::pi / 180;

/// Thrown inside the parser only, caught in parse_map: the first error ends the parse.
struct ParseFailure {
  MapError error;
};

/// A double as short as it reads back, whole numbers in full: "0.001", "-1", "100000", "1e+300".
std::string format(double value) {
  char buffer[32];
  const bool whole = std::abs(value) < 1e15 && value == std::trunc(value);
  const auto [end, error] =
      whole ? std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::fixed)
            : std::to_chars(buffer, buffer + sizeof buffer, value);
  return error == std::errc{} ? std::string(buffer, end) : std::string("?");
}

std::string format(const Vec3& p) {
  return "(" + format(double(p.x())) + ", " + format(double(p.y())) + ", " + format(double(p.z())) +
         ")";
}

/// toml++'s name of a node's type: "string", "integer", "floating-point", "table" ...
std::string type_name(const toml::node& node) {
  std::ostringstream out;
  out << node.type();
  return out.str();
}

int line_of(const toml::node& node) {
  return static_cast<int>(node.source().begin.line);
}

bool is_name(std::string_view text) {
  if (text.empty() || text.size() > kMaxNameChars) return false;
  for (const char c : text) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '-';
    if (!ok) return false;
  }
  return true;
}

/// A relative path below the map's directory: no '..', '.', empty or absolute parts.
bool is_relative_obj_path(std::string_view path) {
  if (path.empty() || path.size() > kMaxPathChars || !path.ends_with(".obj")) return false;
  for (const char c : path) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '-' || c == '.' || c == '/';
    if (!ok) return false;
  }
  std::size_t start = 0;
  while (start <= path.size()) {
    const std::size_t end = std::min(path.find('/', start), path.size());
    const std::string_view part = path.substr(start, end - start);
    if (part.empty() || part == "." || part == "..") return false;
    start = end + 1;
  }
  return true;
}

/// "box 3 (center.y)", "bounds (min.x)", "name".
std::string item_name(const std::string& entry, std::string_view key) {
  if (entry.empty()) return std::string(key);
  if (key.empty()) return entry;
  return entry + " (" + std::string(key) + ")";
}

class Parser {
 public:
  Parser(std::string_view file, const MapFileReader& read) : file_(file), read_(read) {}

  Map parse(std::string_view text) {
    if (text.size() > kMaxMapBytes) {
      std::string message = "expected at most " + std::to_string(kMaxMapBytes) + " bytes, got ";
      message += std::to_string(text.size());
      fail(0, "map", std::move(message));
    }
    map_.files.push_back(MapFile{file_, std::string(text)});
    toml::table root;
    try {
      root = toml::parse(text, std::string_view(file_));
    } catch (const toml::parse_error& error) {
      fail(static_cast<int>(error.source().begin.line), "toml",
           "malformed TOML: " + std::string(error.description()));
    }
    root_ = &root;
    check_keys(root, "", 0,
               {"format", "name", "bounds", "floor_y", "box", "wall", "mesh", "spawn", "pickup",
                "kill_volume"});
    read_header(root);
    read_bounds(root);
    read_floor(root);
    read_boxes(root);
    read_walls(root);
    read_meshes(root);
    read_spawns(root);
    read_pickups(root);
    read_kill_volumes(root);
    check_spawns_outside_kill_volumes();
    return std::move(map_);
  }

 private:
  [[noreturn]] void fail(int line, std::string item, std::string message) const {
    throw ParseFailure{MapError{file_, std::move(item), std::move(message), line}};
  }

  // --- Tables and keys ------------------------------------------------------------------------

  /// Every key of `table` must be one of `known`.
  void check_keys(const toml::table& table, const std::string& entry, int line,
                  std::initializer_list<std::string_view> known) const {
    for (auto&& [key, node] : table) {
      bool found = false;
      for (const std::string_view name : known) found = found || key.str() == name;
      if (found) continue;
      std::string list;
      for (const std::string_view name : known) {
        if (!list.empty()) list += ", ";
        list += name;
      }
      const int at = key.source().begin.line > 0 ? static_cast<int>(key.source().begin.line) : line;
      // An empty key ("" = 1) is a key too: shown as "".
      const std::string shown = key.str().empty() ? "\"\"" : map_text::printable(key.str());
      fail(at, item_name(entry, shown), "unknown key (expected one of " + list + ")");
    }
  }

  const toml::node& required(const toml::table& table, std::string_view key,
                             const std::string& entry, const char* what) const {
    const toml::node* node = table.get(key);
    if (node == nullptr) {
      // A key missing from the top level is about the whole file: no line.
      fail(&table == root_ ? 0 : line_of(table), item_name(entry, key),
           std::string("expected ") + what + ", missing");
    }
    return *node;
  }

  /// The entries of `[[key]]`: an array of tables, at most `cap`.
  std::vector<const toml::table*> entries(const toml::table& root, std::string_view key,
                                          std::size_t cap, const char* plural) const {
    std::vector<const toml::table*> out;
    const toml::node* node = root.get(key);
    if (node == nullptr) return out;
    const toml::array* array = node->as_array();
    if (array == nullptr) {
      fail(line_of(*node), std::string(key),
           "expected an array of tables ([[" + std::string(key) + "]]), got " + type_name(*node));
    }
    if (array->size() > cap) {
      fail(line_of(*node), std::string(key),
           "expected at most " + std::to_string(cap) + " " + plural + ", got " +
               std::to_string(array->size()));
    }
    for (const toml::node& element : *array) {
      const toml::table* table = element.as_table();
      if (table == nullptr) {
        fail(line_of(element), std::string(key) + " " + std::to_string(out.size() + 1),
             std::string("expected a table, got ") + type_name(element));
      }
      out.push_back(table);
    }
    return out;
  }

  // --- Values ---------------------------------------------------------------------------------

  double number(const toml::node& node, const std::string& item, double low, double high) const {
    double value = 0;
    if (const auto* integer = node.as_integer()) {
      value = static_cast<double>(integer->get());
    } else if (const auto* floating = node.as_floating_point()) {
      value = floating->get();
    } else {
      fail(line_of(node), item, "expected a number, got " + type_name(node));
    }
    if (!std::isfinite(value))
      fail(line_of(node), item, "expected a finite number, got " + format(value));
    if (value < low || value > high) {
      fail(line_of(node), item,
           "expected a number in " + format(low) + ".." + format(high) + ", got " + format(value));
    }
    return value;
  }

  double number(const toml::table& table, std::string_view key, const std::string& entry,
                double low, double high) const {
    return number(required(table, key, entry, "a number"), item_name(entry, key), low, high);
  }

  std::optional<double> optional_number(const toml::table& table, std::string_view key,
                                        const std::string& entry, double low, double high) const {
    const toml::node* node = table.get(key);
    if (node == nullptr) return std::nullopt;
    return number(*node, item_name(entry, key), low, high);
  }

  std::int64_t integer(const toml::node& node, const std::string& item, std::int64_t low,
                       std::int64_t high) const {
    const auto* value = node.as_integer();
    if (value == nullptr) {
      fail(line_of(node), item, std::string("expected an integer, got ") + type_name(node));
    }
    if (value->get() < low || value->get() > high) {
      fail(line_of(node), item,
           "expected an integer in " + std::to_string(low) + ".." + std::to_string(high) +
               ", got " + std::to_string(value->get()));
    }
    return value->get();
  }

  std::string string(const toml::table& table, std::string_view key,
                     const std::string& entry) const {
    const toml::node& node = required(table, key, entry, "a string");
    const auto* value = node.as_string();
    if (value == nullptr) {
      fail(line_of(node), item_name(entry, key),
           std::string("expected a string, got ") + type_name(node));
    }
    return value->get();
  }

  std::string name(const toml::table& table, std::string_view key, const std::string& entry) const {
    std::string value = string(table, key, entry);
    if (!is_name(value)) {
      fail(line_of(*table.get(key)), item_name(entry, key),
           "expected 1..32 of A-Z a-z 0-9 _ -, got " + map_text::quote(value));
    }
    return value;
  }

  /// An array of exactly `N` numbers; `axes` names them in errors ("xyz", "xz").
  template <std::size_t N>
  std::array<double, N> numbers(const toml::node& node, const std::string& entry,
                                std::string_view key, const char* axes) const {
    const toml::array* array = node.as_array();
    const std::string item = item_name(entry, key);
    if (array == nullptr || array->size() != N) {
      std::string message = "expected an array of " + std::to_string(N) + " numbers [";
      for (std::size_t k = 0; k < N; ++k) message += std::string(k ? ", " : "") + axes[k];
      message += "], got ";
      message += array ? "an array of " + std::to_string(array->size()) : type_name(node);
      fail(line_of(node), item, std::move(message));
    }
    std::array<double, N> out{};
    for (std::size_t k = 0; k < N; ++k) {
      out[k] = number(*array->get(k), item_name(entry, std::string(key) + "." + axes[k]),
                      -kMaxCoordinate, kMaxCoordinate);
    }
    return out;
  }

  Vec3 point(const toml::node& node, const std::string& entry, std::string_view key) const {
    const std::array<double, 3> p = numbers<3>(node, entry, key, "xyz");
    return Vec3(p[0], p[1], p[2]);
  }

  Vec3 point(const toml::table& table, std::string_view key, const std::string& entry) const {
    return point(required(table, key, entry, "an array [x, y, z] (m)"), entry, key);
  }

  void require_inside(const Vec3& p, int line, const std::string& item) const {
    if (!map_.contains(p)) {
      fail(line, item,
           "expected a point inside the bounds " + format(map_.bounds_min_m) + ".." +
               format(map_.bounds_max_m) + ", got " + format(p));
    }
  }

  /// A point inside the bounds.
  Vec3 placed(const toml::table& table, std::string_view key, const std::string& entry) const {
    const Vec3 p = point(table, key, entry);
    require_inside(p, line_of(*table.get(key)), item_name(entry, key));
    return p;
  }

  float yaw(const toml::table& table, const std::string& entry) const {
    return static_cast<float>(optional_number(table, "yaw_deg", entry, -360, 360).value_or(0) *
                              kRadiansPerDegree);
  }

  // --- Sections -------------------------------------------------------------------------------

  void read_header(const toml::table& root) {
    integer(required(root, "format", "", "the format version (format = 1)"), "format",
            kFormatVersion, kFormatVersion);
    map_.name = name(root, "name", "");
  }

  void read_bounds(const toml::table& root) {
    const toml::node& node = required(root, "bounds", "", "a table [bounds] with min and max");
    const toml::table* bounds = node.as_table();
    if (bounds == nullptr) {
      fail(line_of(node), "bounds", std::string("expected a table, got ") + type_name(node));
    }
    check_keys(*bounds, "bounds", line_of(node), {"min", "max"});
    map_.bounds_min_m = point(*bounds, "min", "bounds");
    map_.bounds_max_m = point(*bounds, "max", "bounds");
    static const char* const kAxes[] = {"max.x", "max.y", "max.z"};
    for (int axis = 0; axis < 3; ++axis) {
      const double low = double(map_.bounds_min_m[axis]);
      const double high = double(map_.bounds_max_m[axis]);
      if (!(high - low >= kMinBoundsSpan)) {
        fail(line_of(*bounds->get("max")), item_name("bounds", kAxes[axis]),
             "expected at least min + " + format(kMinBoundsSpan) + " = " +
                 format(low + kMinBoundsSpan) + ", got " + format(high));
      }
    }
  }

  void read_floor(const toml::table& root) {
    const toml::node* node = root.get("floor_y");
    if (node == nullptr) return;
    map_.floor_y_m = static_cast<float>(
        number(*node, "floor_y", double(map_.bounds_min_m.y()), double(map_.bounds_max_m.y())));
  }

  void add_box(const MapBox& box, int line, const std::string& entry) {
    if (map_.boxes.size() >= kMaxBoxes) {
      fail(line, entry,
           "expected at most " + std::to_string(kMaxBoxes) + " boxes and walls together, got more");
    }
    map_.boxes.push_back(box);
  }

  void read_boxes(const toml::table& root) {
    std::size_t number_of = 0;
    for (const toml::table* table : entries(root, "box", kMaxBoxes, "boxes")) {
      const std::string entry = "box " + std::to_string(++number_of);
      check_keys(*table, entry, line_of(*table), {"center", "half_extents", "yaw_deg"});
      MapBox box;
      box.center_m = placed(*table, "center", entry);
      const toml::node& extents = required(*table, "half_extents", entry, "an array [x, y, z] (m)");
      const std::array<double, 3> half = numbers<3>(extents, entry, "half_extents", "xyz");
      static const char* const kKeys[] = {"half_extents.x", "half_extents.y", "half_extents.z"};
      for (int axis = 0; axis < 3; ++axis) {
        if (!(half[axis] >= kMinSize)) {
          fail(line_of(extents), item_name(entry, kKeys[axis]),
               "expected a number >= " + format(kMinSize) + ", got " + format(half[axis]));
        }
      }
      box.half_extents_m = Vec3(half[0], half[1], half[2]);
      box.yaw_rad = yaw(*table, entry);
      add_box(box, line_of(*table), entry);
    }
  }

  void read_walls(const toml::table& root) {
    std::size_t number_of = 0;
    for (const toml::table* table : entries(root, "wall", kMaxBoxes, "walls")) {
      const std::string entry = "wall " + std::to_string(++number_of);
      check_keys(*table, entry, line_of(*table), {"from", "to", "base", "height", "thickness"});
      const std::array<double, 2> from =
          numbers<2>(required(*table, "from", entry, "an array [x, z] (m)"), entry, "from", "xz");
      const toml::node& to_node = required(*table, "to", entry, "an array [x, z] (m)");
      const std::array<double, 2> to = numbers<2>(to_node, entry, "to", "xz");
      const double base = number(*table, "base", entry, -kMaxCoordinate, kMaxCoordinate);
      const double height = number(*table, "height", entry, 2 * kMinSize, kMaxCoordinate);
      const double thickness = number(*table, "thickness", entry, 2 * kMinSize, kMaxCoordinate);
      const double length = std::hypot(to[0] - from[0], to[1] - from[1]);
      if (!(length >= 2 * kMinSize)) {
        fail(line_of(to_node), item_name(entry, "to"),
             "expected an end at least " + format(2 * kMinSize) + " m from the start, got " +
                 format(length) + " m");
      }
      MapBox box;
      box.center_m = Vec3((from[0] + to[0]) / 2, base + height / 2, (from[1] + to[1]) / 2);
      require_inside(box.center_m, line_of(*table), item_name(entry, "centre"));
      box.half_extents_m = Vec3(length / 2, height / 2, thickness / 2);
      // The box's local +X runs along the wall; yaw turns +X towards -Z.
      box.yaw_rad = static_cast<float>(std::atan2(-(to[1] - from[1]), to[0] - from[0]));
      add_box(box, line_of(*table), entry);
    }
  }

  void read_meshes(const toml::table& root) {
    std::size_t number_of = 0;
    for (const toml::table* table : entries(root, "mesh", kMaxMeshes, "meshes")) {
      const std::string entry = "mesh " + std::to_string(++number_of);
      check_keys(*table, entry, line_of(*table), {"name", "vertices", "triangles", "obj"});
      MapMesh mesh;
      mesh.name = name(*table, "name", entry);
      for (std::size_t k = 0; k + 1 < number_of; ++k) {
        if (map_.meshes[k].name == mesh.name) {
          fail(line_of(*table->get("name")), item_name(entry, "name"),
               "expected a name no other mesh has, got " + map_text::quote(mesh.name) +
                   " (also mesh " + std::to_string(k + 1) + ")");
        }
      }
      if (table->get("obj") != nullptr) {
        if (table->get("vertices") != nullptr || table->get("triangles") != nullptr) {
          fail(line_of(*table), entry, "expected either obj or vertices and triangles, got both");
        }
        read_obj_mesh(*table, entry, mesh);
      } else {
        read_inline_mesh(*table, entry, mesh);
      }
      map_.meshes.push_back(std::move(mesh));
    }
  }

  void read_inline_mesh(const toml::table& table, const std::string& entry, MapMesh& mesh) {
    const toml::node& vertices_node =
        required(table, "vertices", entry, "an array of [x, y, z] (or obj = \"FILE.obj\")");
    const toml::array* vertices = vertices_node.as_array();
    if (vertices == nullptr || vertices->empty() || vertices->size() > kMaxMeshVertices) {
      fail(
          line_of(vertices_node), item_name(entry, "vertices"),
          "expected an array of 1.." + std::to_string(kMaxMeshVertices) +
              " points [x, y, z], got " +
              (vertices ? std::to_string(vertices->size()) + " points" : type_name(vertices_node)));
    }
    for (std::size_t k = 0; k < vertices->size(); ++k) {
      const std::string key = "vertices " + std::to_string(k);
      const toml::node& node = *vertices->get(k);
      const Vec3 p = point(node, entry, key);
      require_inside(p, line_of(node), item_name(entry, key));
      mesh.vertices_m.push_back(p);
    }
    const toml::node& triangles_node = required(table, "triangles", entry, "an array of [a, b, c]");
    const toml::array* triangles = triangles_node.as_array();
    if (triangles == nullptr || triangles->empty() || triangles->size() > kMaxMeshTriangles) {
      fail(line_of(triangles_node), item_name(entry, "triangles"),
           "expected an array of 1.." + std::to_string(kMaxMeshTriangles) +
               " triangles [a, b, c], got " +
               (triangles ? std::to_string(triangles->size()) + " triangles"
                          : type_name(triangles_node)));
    }
    const auto last = static_cast<std::int64_t>(mesh.vertices_m.size()) - 1;
    for (std::size_t k = 0; k < triangles->size(); ++k) {
      const std::string item = item_name(entry, "triangles " + std::to_string(k));
      const toml::node& node = *triangles->get(k);
      const toml::array* corners = node.as_array();
      if (corners == nullptr || corners->size() != 3) {
        fail(line_of(node), item,
             std::string("expected three vertex numbers [a, b, c], got ") +
                 (corners ? "an array of " + std::to_string(corners->size()) : type_name(node)));
      }
      std::uint32_t corner[3];
      for (std::size_t c = 0; c < 3; ++c) {
        corner[c] = static_cast<std::uint32_t>(integer(*corners->get(c), item, 0, last));
      }
      const Vec3& a = mesh.vertices_m[corner[0]];
      const Vec3 normal = (mesh.vertices_m[corner[1]] - a).cross(mesh.vertices_m[corner[2]] - a);
      if (!(normal.norm() > physics::Real(1e-6))) {
        fail(line_of(node), item, "expected corners enclosing an area, got a degenerate triangle");
      }
      mesh.indices.insert(mesh.indices.end(), corner, corner + 3);
    }
  }

  void read_obj_mesh(const toml::table& table, const std::string& entry, MapMesh& mesh) {
    const std::string path = string(table, "obj", entry);
    const int line = line_of(*table.get("obj"));
    const std::string item = item_name(entry, "obj");
    if (!is_relative_obj_path(path)) {
      fail(line, item,
           "expected a relative path to a .obj file below the map's directory (1..128 of "
           "A-Z a-z 0-9 _ - . /, no '..'), got " +
               map_text::quote(path));
    }
    if (!read_)
      fail(line, item, "cannot read " + map_text::quote(path) + ": this parse has no file reader");
    const std::string* text = nullptr;
    for (std::size_t k = 1; k < map_.files.size(); ++k) {
      if (map_.files[k].path == path) text = &map_.files[k].text;
    }
    if (text == nullptr) {
      if (map_.files.size() - 1 >= kMaxObjFiles) {
        fail(line, item,
             "expected at most " + std::to_string(kMaxObjFiles) + " OBJ files, got more");
      }
      std::string error;
      std::optional<std::string> read = read_(path, error);
      if (!read) fail(line, item, "cannot read " + map_text::quote(path) + ": " + error);
      map_.files.push_back(MapFile{path, std::move(*read)});
      text = &map_.files.back().text;
    }
    const std::string shown = (std::filesystem::path(file_).parent_path() / path).string();
    std::variant<MapMesh, MapError> read = parse_obj(*text, shown, entry + " '" + mesh.name + "'");
    if (MapError* error = std::get_if<MapError>(&read)) throw ParseFailure{std::move(*error)};
    MapMesh& loaded = std::get<MapMesh>(read);
    for (std::size_t k = 0; k < loaded.vertices_m.size(); ++k) {
      if (!map_.contains(loaded.vertices_m[k])) {
        fail(line, item,
             "expected every vertex inside the bounds " + format(map_.bounds_min_m) + ".." +
                 format(map_.bounds_max_m) + ", got vertex " + std::to_string(k + 1) + " at " +
                 format(loaded.vertices_m[k]));
      }
    }
    mesh.vertices_m = std::move(loaded.vertices_m);
    mesh.indices = std::move(loaded.indices);
  }

  void read_spawns(const toml::table& root) {
    const std::vector<const toml::table*> tables = entries(root, "spawn", kMaxSpawns, "spawns");
    if (tables.empty()) fail(0, "spawn", "expected at least one [[spawn]], got none");
    int first_team_line = 0;
    std::size_t teams[3] = {0, 0, 0};
    std::size_t number_of = 0;
    for (const toml::table* table : tables) {
      const std::string entry = "spawn " + std::to_string(++number_of);
      check_keys(*table, entry, line_of(*table), {"position", "yaw_deg", "team"});
      MapSpawn spawn;
      spawn.position_m = placed(*table, "position", entry);
      spawn.yaw_rad = yaw(*table, entry);
      if (table->get("team") != nullptr) {
        const std::string team = string(*table, "team", entry);
        if (team == "red") {
          spawn.team = Team::Red;
        } else if (team == "blue") {
          spawn.team = Team::Blue;
        } else {
          fail(line_of(*table->get("team")), item_name(entry, "team"),
               "expected \"red\" or \"blue\" (no key: any player), got " + map_text::quote(team));
        }
        if (first_team_line == 0) first_team_line = line_of(*table);
      }
      ++teams[static_cast<std::size_t>(spawn.team)];
      map_.spawns.push_back(spawn);
      spawn_lines_.push_back(line_of(*table));
    }
    if ((teams[1] == 0) != (teams[2] == 0)) {
      fail(first_team_line, "spawn",
           "expected team spawns for both teams or for none, got " + std::to_string(teams[1]) +
               " red and " + std::to_string(teams[2]) + " blue");
    }
  }

  void read_pickups(const toml::table& root) {
    std::size_t number_of = 0;
    for (const toml::table* table : entries(root, "pickup", kMaxPickups, "pickups")) {
      const std::string entry = "pickup " + std::to_string(++number_of);
      check_keys(*table, entry, line_of(*table), {"kind", "position", "amount", "respawn_s"});
      MapPickup pickup;
      const std::string kind = string(*table, "kind", entry);
      if (kind == "health") {
        pickup.kind = PickupKind::Health;
      } else if (kind == "armor") {
        pickup.kind = PickupKind::Armor;
      } else if (kind == "ammo") {
        pickup.kind = PickupKind::Ammo;
      } else {
        fail(line_of(*table->get("kind")), item_name(entry, "kind"),
             "expected \"health\", \"armor\" or \"ammo\", got " + map_text::quote(kind));
      }
      pickup.position_m = placed(*table, "position", entry);
      const std::int64_t most = pickup.kind == PickupKind::Ammo ? 100 : 200;
      pickup.amount = static_cast<int>(integer(required(*table, "amount", entry, "an integer"),
                                               item_name(entry, "amount"), 1, most));
      pickup.respawn_s = static_cast<float>(number(*table, "respawn_s", entry, 1, 600));
      map_.pickups.push_back(pickup);
    }
  }

  void read_kill_volumes(const toml::table& root) {
    std::size_t number_of = 0;
    for (const toml::table* table : entries(root, "kill_volume", kMaxKillVolumes, "kill volumes")) {
      const std::string entry = "kill_volume " + std::to_string(++number_of);
      check_keys(*table, entry, line_of(*table), {"name", "min", "max"});
      MapKillVolume volume;
      volume.name = name(*table, "name", entry);
      for (std::size_t k = 0; k + 1 < number_of; ++k) {
        if (map_.kill_volumes[k].name == volume.name) {
          fail(line_of(*table->get("name")), item_name(entry, "name"),
               "expected a name no other kill volume has, got " + map_text::quote(volume.name) +
                   " (also kill_volume " + std::to_string(k + 1) + ")");
        }
      }
      volume.min_m = placed(*table, "min", entry);
      volume.max_m = placed(*table, "max", entry);
      static const char* const kAxes[] = {"max.x", "max.y", "max.z"};
      for (int axis = 0; axis < 3; ++axis) {
        const double low = double(volume.min_m[axis]);
        const double high = double(volume.max_m[axis]);
        if (!(high - low >= kMinKillSpan)) {
          fail(line_of(*table->get("max")), item_name(entry, kAxes[axis]),
               "expected at least min + " + format(kMinKillSpan) + " = " +
                   format(low + kMinKillSpan) + ", got " + format(high));
        }
      }
      map_.kill_volumes.push_back(std::move(volume));
    }
  }

  /// A player must not be born dead.
  void check_spawns_outside_kill_volumes() const {
    for (std::size_t s = 0; s < map_.spawns.size(); ++s) {
      for (const MapKillVolume& volume : map_.kill_volumes) {
        if (volume.contains(map_.spawns[s].position_m)) {
          fail(spawn_lines_[s], "spawn " + std::to_string(s + 1),
               "expected a position outside every kill volume, got " +
                   format(map_.spawns[s].position_m) + " inside " + map_text::quote(volume.name));
        }
      }
    }
  }

  std::string file_;
  const MapFileReader& read_;
  const toml::table* root_ = nullptr;
  Map map_;
  std::vector<int> spawn_lines_;  ///< of each spawn's table, for the kill volume check
};

}  // namespace

MapResult parse_map(std::string_view text, std::string_view file, const MapFileReader& read) {
  try {
    return Parser(file, read).parse(text);
  } catch (const ParseFailure& failure) {
    return failure.error;
  } catch (const std::exception& error) {
    // Not expected (a reader that throws, memory): reported, never let out.
    return MapError{std::string(file), "map", std::string("cannot load: ") + error.what(), 0};
  }
}

}  // namespace ricochet::server
