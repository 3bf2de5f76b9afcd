#pragma once
/// The test every counted enum gets (CONTRIBUTING.md, "Counted enums"): each value below the
/// count has a name of its own, and the count itself has none. The compiler already refuses a
/// name() switch that misses an enumerator (-Wswitch is an error); this catches the other
/// mistake, an enumerator added after the last one without the count line following it.

#include <gtest/gtest.h>

#include <cstddef>
#include <set>
#include <string>

namespace ricochet::test {

/// name_of(Enum) returns the enumerator's name, and `unknown` for a value that is none.
template <class Enum, class NameOf>
void expect_counted(std::size_t count, NameOf name_of, const std::string& unknown = "unknown") {
  std::set<std::string> names;
  for (std::size_t i = 0; i < count; ++i) {
    const std::string name{name_of(static_cast<Enum>(i))};
    EXPECT_NE(name, unknown) << "value " << i << " of " << count << " has no name";
    EXPECT_TRUE(names.insert(name).second) << "two values are named " << name;
  }
  EXPECT_EQ(std::string{name_of(static_cast<Enum>(count))}, unknown)
      << "value " << count << " has a name: the count stops short of the last enumerator";
}

}  // namespace ricochet::test
