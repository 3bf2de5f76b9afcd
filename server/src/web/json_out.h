#pragma once
/// What the dashboard's JSON documents share (map_view.h, frame_json.h): numbers written so they
/// stay valid JSON, strings escaped, the game's enums by name.

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "ricochet/server/map.h"

namespace ricochet::server::web {

/// `value` with at most `decimals` digits after the point, trailing zeros dropped ("1.5", "-3",
/// "0"); null when it is not finite.
void append_number(std::string& out, double value, int decimals = 3);
/// `value` as [x,y,z], each as append_number writes it.
void append_vec3(std::string& out, const std::array<float, 3>& value, int decimals = 3);
/// `text` as a JSON string, quotes included.
void append_string(std::string& out, std::string_view text);
/// "red", "blue", or null for Team::None.
void append_team(std::string& out, Team team);

/// `items` as a JSON array, each written by `append(out, item)`.
template <typename Item, typename Append>
void append_array(std::string& out, const std::vector<Item>& items, Append append) {
  out += '[';
  for (std::size_t k = 0; k < items.size(); ++k) {
    if (k > 0) out += ',';
    append(out, items[k]);
  }
  out += ']';
}

}  // namespace ricochet::server::web
