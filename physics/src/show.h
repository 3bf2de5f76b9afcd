#pragma once
/// Values as text for error messages.

#include <sstream>
#include <string>

#include "math_util.h"

namespace ricochet::physics {

template <class T>
std::string show(const T& value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

inline std::string show(const Vec3& v) {
  std::ostringstream out;
  out << '(' << v.x() << ", " << v.y() << ", " << v.z() << ')';
  return out.str();
}

}  // namespace ricochet::physics
