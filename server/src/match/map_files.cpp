/// Maps from disk and from recorded files (map.h load_map_file, parse_map_files), and the small
/// members of the map types.

#include <filesystem>
#include <fstream>
#include <system_error>

#include "ricochet/server/map.h"

namespace ricochet::server {

namespace {

/// The file at `path`, at most `cap` bytes; nullopt with `error` set when it cannot be read.
std::optional<std::string> read_capped(const std::filesystem::path& path, std::size_t cap,
                                       std::string& error) {
  std::error_code status;
  if (!std::filesystem::is_regular_file(path, status)) {
    error = "expected a readable file at " + path.string();
    return std::nullopt;
  }
  std::ifstream file(path, std::ios::binary);
  std::string text(cap + 1, '\0');
  if (file) file.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (!file && !file.eof()) {
    error = "could not read " + path.string();
    return std::nullopt;
  }
  text.resize(static_cast<std::size_t>(file.gcount()));
  if (text.size() > cap) {
    error = "expected at most ";
    error += std::to_string(cap) + " bytes in " + path.string() + ", got more";
    return std::nullopt;
  }
  return text;
}

}  // namespace

bool Map::contains(const physics::Vec3& point_m) const {
  return (point_m.array() >= bounds_min_m.array()).all() &&
         (point_m.array() <= bounds_max_m.array()).all();
}

bool MapKillVolume::contains(const physics::Vec3& point_m) const {
  return (point_m.array() >= min_m.array()).all() && (point_m.array() <= max_m.array()).all();
}

std::string MapError::describe() const {
  std::string out = file;
  if (line > 0) {
    out += ':';
    out += std::to_string(line);
  }
  out += ": ";
  if (!item.empty()) {
    out += item;
    out += ": ";
  }
  out += message;
  return out;
}

MapResult load_map_file(const std::string& path) {
  std::string error;
  std::optional<std::string> text = read_capped(path, kMaxMapBytes, error);
  if (!text) return MapError{path, "map", error, 0};
  const std::filesystem::path directory = std::filesystem::path(path).parent_path();
  const MapFileReader read = [&directory](std::string_view name, std::string& why) {
    return read_capped(directory / name, kMaxObjBytes, why);
  };
  return parse_map(*text, path, read);
}

MapResult parse_map_files(std::span<const MapFile> files) {
  if (files.empty()) return MapError{"<map>", "map", "expected the map file, got no files", 0};
  const MapFileReader read = [files](std::string_view name,
                                     std::string& why) -> std::optional<std::string> {
    for (const MapFile& file : files.subspan(1)) {
      if (file.path == name) return file.text;
    }
    why = "not among the " + std::to_string(files.size() - 1) + " files given with the map";
    return std::nullopt;
  };
  MapResult result = parse_map(files[0].text, files[0].path, read);
  if (const Map* map = std::get_if<Map>(&result); map && map->files.size() != files.size()) {
    // The map read each file it names once; anything more given is not part of it.
    return MapError{files[0].path, "map",
                    "expected the map and the " + std::to_string(map->files.size() - 1) +
                        " files it names, got " + std::to_string(files.size() - 1) + " files",
                    0};
  }
  return result;
}

}  // namespace ricochet::server
