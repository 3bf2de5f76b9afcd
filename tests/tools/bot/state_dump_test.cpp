#include "ricochet/bot/state_dump.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "temp_dir.h"

namespace ricochet::bot::state_dump_test {
namespace {

proto::QuantizedEntity entity(std::uint32_t id, Vec3 position, std::uint8_t flags = 0) {
  proto::EntityState state;
  state.id = id;
  state.position_m = position;
  state.flags = flags;
  return proto::quantize(state, proto::QuantizationSpec{});
}

std::string contents(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(StateDump, WritesEachSnapshotsPlayersAsDecodedAndNoProjectiles) {
  ricochet::test::TempDir dir("state-dump");
  const auto path = dir.path() / "states.csv";
  std::string error;
  auto dump = StateDump::create(path.string(), error);
  ASSERT_TRUE(dump) << error;
  WorldView view{proto::QuantizationSpec{}};
  view.apply_snapshot(
      100, 1,
      std::vector{entity(1, {1.25f, 0.5f, -3.0f}),
                  entity(2, {0.0014f, 2.0f, 7.1237f}, proto::kEntityDead),
                  entity(3, {5, 5, 5}, proto::kind_flags(proto::EntityKind::Rocket))});
  dump->write(view);
  view.apply_snapshot(103, 1, std::vector{entity(2, {-4.5f, 0.45f, 9.0f})});
  dump->write(view);
  dump.reset();  // closes the file

  // The dequantised values, printed as ricochet-replay --export prints positions.
  const auto line = [](std::uint32_t tick, const SeenEntity& seen) {
    char text[128];
    std::snprintf(text, sizeof text, "%u,%u,%.9g,%.9g,%.9g\n", tick, seen.id, seen.position_m[0],
                  seen.position_m[1], seen.position_m[2]);
    return std::string(text);
  };
  WorldView expected{proto::QuantizationSpec{}};
  expected.apply_snapshot(100, 1,
                          std::vector{entity(1, {1.25f, 0.5f, -3.0f}),
                                      entity(2, {0.0014f, 2.0f, 7.1237f}, proto::kEntityDead)});
  // On the quantisation grid (1 mm), not as given.
  EXPECT_NE(expected.find(2)->position_m[0], 0.0014f);
  EXPECT_NEAR(expected.find(2)->position_m[0], 0.0014f, 0.0006f);
  std::string want =
      "tick,entity,x,y,z\n" + line(100, *expected.find(1)) + line(100, *expected.find(2));
  expected.apply_snapshot(103, 1, std::vector{entity(2, {-4.5f, 0.45f, 9.0f})});
  want += line(103, *expected.find(2));
  EXPECT_EQ(contents(path), want);
}

TEST(StateDump, AFileThatCannotBeWrittenIsAnError) {
  std::string error;
  EXPECT_FALSE(StateDump::create("/nonexistent-dir/states.csv", error));
  EXPECT_NE(error.find("/nonexistent-dir/states.csv"), std::string::npos) << error;
}

}  // namespace
}  // namespace ricochet::bot::state_dump_test
