#pragma once
/// The checks every config of the match library validates its fields with, so that every
/// message reads the same: "<owner> <field> must be <range>, got <value>".

#include <cmath>
#include <string>
#include <string_view>

namespace ricochet::server {

/// Finite and within [low, high].
inline bool within(double value, double low, double high) {
  return std::isfinite(value) && value >= low && value <= high;
}

/// "movement friction must be 0..1000, got -1.000000"; integers print as integers.
template <typename Number>
std::string range_error(std::string_view owner, std::string_view field, std::string_view range,
                        Number value) {
  std::string message(owner);
  message += ' ';
  message += field;
  message += " must be ";
  message += range;
  message += ", got ";
  message += std::to_string(value);
  return message;
}

}  // namespace ricochet::server
