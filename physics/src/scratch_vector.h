#pragma once
/// Per-step buffers are reused, so a warm world steps without allocating. std::vector::assign
/// reallocates to exactly the new size whenever it exceeds the capacity, so a count that creeps
/// up would reallocate at every new maximum; these grow the capacity geometrically instead.

#include <algorithm>
#include <iterator>
#include <type_traits>
#include <vector>

namespace ricochet::physics {

/// v = n copies of value.
template <class T>
void assign_reusing(std::vector<T>& v, std::size_t n, const std::type_identity_t<T>& value) {
  if (n > v.capacity()) v.reserve(std::max(n, 2 * v.capacity()));
  v.assign(n, value);
}

/// v = [first, last).
template <class T, std::input_iterator It>
void assign_reusing(std::vector<T>& v, It first, It last) {
  const auto n = static_cast<std::size_t>(std::distance(first, last));
  if (n > v.capacity()) v.reserve(std::max(n, 2 * v.capacity()));
  v.assign(first, last);
}

}  // namespace ricochet::physics
