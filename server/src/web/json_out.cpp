/// The dashboard's JSON helpers (json_out.h).

#include "json_out.h"

#include <cmath>
#include <cstdio>

#include "ricochet/tools/json_text.h"

namespace ricochet::server::web {

void append_number(std::string& out, double value, int decimals) {
  if (!std::isfinite(value)) {
    out += "null";
    return;
  }
  char text[64];
  const int length = std::snprintf(text, sizeof text, "%.*f", decimals, value);
  std::string_view written(text, static_cast<std::size_t>(length));
  if (written.find('.') != std::string_view::npos) {
    while (written.back() == '0') written.remove_suffix(1);
    if (written.back() == '.') written.remove_suffix(1);
  }
  if (written == "-0") written = "0";
  out += written;
}

void append_vec3(std::string& out, const std::array<float, 3>& value, int decimals) {
  out += '[';
  for (std::size_t axis = 0; axis < 3; ++axis) {
    if (axis > 0) out += ',';
    append_number(out, value[axis], decimals);
  }
  out += ']';
}

void append_string(std::string& out, std::string_view text) {
  out += tools::json_string(text);
}

void append_team(std::string& out, Team team) {
  switch (team) {
    case Team::Red:
      out += "\"red\"";
      return;
    case Team::Blue:
      out += "\"blue\"";
      return;
    case Team::None:
      break;
  }
  out += "null";
}

}  // namespace ricochet::server::web
