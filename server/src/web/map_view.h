#pragma once
/// A map's static geometry for a top-down view (issue 32, "A match, live"): one JSON document a
/// page draws once, then moves the live frames (frame_json.h) over it.
///
/// Axes as the physics world has them: metres, +Y up, so the ground plane is x-z (a page maps x
/// right and z down, and sees the map from above). Yaw is about +Y, counter-clockwise seen from
/// above, 0 facing -Z. The document:
///   {"map": name,
///    "axes": {"up": "+y", "ground": ["x", "z"], "yaw_zero": "-z", "yaw_turn": "ccw_from_above"},
///    "bounds": {"min": [x,y,z], "max": [x,y,z]},
///    "floor_y": y or null (the plane y = floor_y, solid below),
///    "boxes": [{"corners": [[x,z] × 4], "y_min": y, "y_max": y}]  (boxes and walls, their yaw
///              applied: the corners in order round the rectangle),
///    "meshes": [{"name": s, "vertices": [[x,z]...], "heights": [y...] (one per vertex),
///               "triangles": [[i,j,k]...]}],
///    "spawns": [{"position": [x,y,z], "yaw": rad, "team": "red"|"blue"|null}],
///    "pickups": [{"kind": "health"|"armor"|"ammo", "position": [x,y,z]}],
///    "kill_volumes": [{"name": s, "min": [x,y,z], "max": [x,y,z]}]}
/// Coordinates in metres to the millimetre, angles in radians to 1e-4.

#include <string>

#include "ricochet/server/map.h"

namespace ricochet::server::web {

/// The top-down view of `map` (a loaded, hence validated, map) as the document above.
std::string map_view_json(const Map& map);

}  // namespace ricochet::server::web
