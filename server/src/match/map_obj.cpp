/// Wavefront OBJ meshes for maps (map.h parse_obj): vertices and faces, fanned into triangles.

#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <system_error>

#include "map_text.h"
#include "ricochet/server/map.h"

namespace ricochet::server {

namespace {

using physics::Vec3;

constexpr std::size_t kMaxVertices = 65536;
constexpr std::size_t kMaxTriangles = 65536;
constexpr std::size_t kMaxFaceCorners = 64;
constexpr double kMaxCoordinate = 100000;

/// Thrown inside the reader only, caught in parse_obj: the first error ends the read.
struct ObjFailure {
  MapError error;
};

class ObjReader {
 public:
  ObjReader(std::string_view text, std::string_view file, std::string_view item)
      : text_(text), file_(file), item_(item) {}

  MapMesh read() {
    if (text_.size() > kMaxObjBytes) {
      std::string message = "expected at most " + std::to_string(kMaxObjBytes) + " bytes, got ";
      message += std::to_string(text_.size());
      fail(0, std::move(message));
    }
    while (next_line()) statement();
    if (mesh_.indices.empty()) fail(0, "expected at least one face ('f' line), got none");
    return std::move(mesh_);
  }

 private:
  [[noreturn]] void fail(int line, std::string message) const {
    throw ObjFailure{MapError{file_, item_, std::move(message), line}};
  }
  [[noreturn]] void fail(std::string message) const { fail(line_, std::move(message)); }

  /// Splits the next line that has anything but a comment into tokens_.
  bool next_line() {
    while (position_ < text_.size()) {
      const std::size_t end = std::min(text_.find('\n', position_), text_.size());
      std::string_view line = text_.substr(position_, end - position_);
      position_ = end + 1;
      ++line_;
      line = line.substr(0, line.find('#'));
      tokens_.clear();
      std::size_t at = 0;
      while (at < line.size()) {
        const std::size_t start = line.find_first_not_of(" \t\r", at);
        if (start == std::string_view::npos) break;
        const std::size_t stop = std::min(line.find_first_of(" \t\r", start), line.size());
        if (tokens_.size() > kMaxFaceCorners) {
          fail("expected at most " + std::to_string(kMaxFaceCorners) + " values after the keyword");
        }
        tokens_.push_back(line.substr(start, stop - start));
        at = stop;
      }
      if (!tokens_.empty()) return true;
    }
    return false;
  }

  void statement() {
    const std::string_view keyword = tokens_[0];
    if (keyword == "v") return vertex();
    if (keyword == "f") return face();
    if (keyword == "vt") {
      ++texture_coordinates_;
      return;
    }
    if (keyword == "vn") {
      ++normals_;
      return;
    }
    if (keyword == "vp" || keyword == "o" || keyword == "g" || keyword == "s" ||
        keyword == "usemtl" || keyword == "mtllib") {
      return;
    }
    fail("expected one of v, vt, vn, vp, f, o, g, s, usemtl, mtllib, got " +
         map_text::quote(keyword));
  }

  void vertex() {
    if (tokens_.size() != 4 && tokens_.size() != 5) {
      fail("expected 'v X Y Z [W]', got " + std::to_string(tokens_.size() - 1) + " values");
    }
    if (mesh_.vertices_m.size() >= kMaxVertices) {
      fail("expected at most " + std::to_string(kMaxVertices) + " vertices, got more");
    }
    double xyz[3];
    for (int k = 0; k < 3; ++k) {
      const std::string_view token = tokens_[1 + static_cast<std::size_t>(k)];
      const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), xyz[k]);
      if (error != std::errc{} || end != token.data() + token.size() || !std::isfinite(xyz[k]) ||
          std::abs(xyz[k]) > kMaxCoordinate) {
        fail("vertex " + std::to_string(mesh_.vertices_m.size() + 1) +
             ": expected a decimal number within +-100000, got " + map_text::quote(token));
      }
    }
    mesh_.vertices_m.emplace_back(xyz[0], xyz[1], xyz[2]);
  }

  /// One index of a face corner: 1-based, or negative counting back from the last one read.
  std::uint32_t index(std::string_view token, std::size_t count, const char* what) const {
    std::int64_t value = 0;
    const auto [end, error] = std::from_chars(token.data(), token.data() + token.size(), value);
    const auto size = static_cast<std::int64_t>(count);
    if (error != std::errc{} || end != token.data() + token.size() || value == 0 || value > size ||
        value < -size) {
      std::string message = "expected a";
      message += what;
      message += count == 0
                     ? " index, but none is defined yet"
                     : " index 1.." + std::to_string(count) + " or -1..-" + std::to_string(count);
      message += ", got " + map_text::quote(token);
      fail(std::move(message));
    }
    return static_cast<std::uint32_t>(value > 0 ? value - 1 : size + value);
  }

  /// A corner: v, v/vt, v/vt/vn or v//vn.
  std::uint32_t corner(std::string_view token) const {
    const std::size_t first = token.find('/');
    const std::uint32_t vertex = index(token.substr(0, first), mesh_.vertices_m.size(), " vertex");
    if (first == std::string_view::npos) return vertex;
    const std::string_view rest = token.substr(first + 1);
    const std::size_t second = rest.find('/');
    const std::string_view texture = rest.substr(0, second);
    if (second == std::string_view::npos) {
      index(texture, texture_coordinates_, " texture coordinate (vt)");
      return vertex;
    }
    if (!texture.empty()) index(texture, texture_coordinates_, " texture coordinate (vt)");
    index(rest.substr(second + 1), normals_, " normal (vn)");
    return vertex;
  }

  void face() {
    if (tokens_.size() < 4) {
      fail("expected a face of at least 3 corners, got " + std::to_string(tokens_.size() - 1));
    }
    std::uint32_t corners[kMaxFaceCorners];
    for (std::size_t k = 1; k < tokens_.size(); ++k) corners[k - 1] = corner(tokens_[k]);
    const std::size_t count = tokens_.size() - 1;
    if (mesh_.indices.size() / 3 + (count - 2) > kMaxTriangles) {
      fail("expected at most " + std::to_string(kMaxTriangles) + " triangles, got more");
    }
    // A fan from the first corner: a convex polygon of n corners is n - 2 triangles.
    for (std::size_t k = 1; k + 1 < count; ++k) {
      const Vec3& a = mesh_.vertices_m[corners[0]];
      const Vec3 normal =
          (mesh_.vertices_m[corners[k]] - a).cross(mesh_.vertices_m[corners[k + 1]] - a);
      if (!(normal.norm() > physics::Real(1e-6))) {
        fail("expected corners enclosing an area, got a degenerate triangle (corners 1, " +
             std::to_string(k + 1) + ", " + std::to_string(k + 2) + ")");
      }
      mesh_.indices.insert(mesh_.indices.end(), {corners[0], corners[k], corners[k + 1]});
    }
  }

  std::string_view text_;
  std::string file_;
  std::string item_;
  std::size_t position_ = 0;
  int line_ = 0;
  std::vector<std::string_view> tokens_;
  std::size_t texture_coordinates_ = 0;
  std::size_t normals_ = 0;
  MapMesh mesh_;
};

}  // namespace

std::variant<MapMesh, MapError> parse_obj(std::string_view text, std::string_view file,
                                          std::string_view item) {
  try {
    return ObjReader(text, file, item).read();
  } catch (const ObjFailure& failure) {
    return failure.error;
  }
}

}  // namespace ricochet::server
