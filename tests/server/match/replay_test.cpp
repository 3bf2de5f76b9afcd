// The replay driver (replay.h) over a stand-in simulation whose hash mixes every event and input
// it was given: a recording replays with every hash matching, one flipped input is caught at the
// first hash after it, skipped ticks are stepped, the wall clock is the injected one.

#include "ricochet/server/replay.h"

#include <gtest/gtest.h>

#include <bit>
#include <string>
#include <variant>
#include <vector>

namespace ricochet::server::replay_test {
namespace {

class MixingSimulation final : public ReplaySimulation {
 public:
  void apply(const RecordedEvent& event) override {
    mix(static_cast<std::uint64_t>(event.kind));
    mix(event.account);
    for (const char c : event.name) mix(static_cast<unsigned char>(c));
  }
  void step(std::span<const RecordedInput> inputs) override {
    ++steps_;
    mix(steps_);
    for (const RecordedInput& input : inputs) {
      mix(input.entity_id);
      mix(input.input.sequence);
      mix(std::bit_cast<std::uint32_t>(input.input.yaw_rad));
      mix(input.input.buttons);
    }
  }
  std::uint64_t state_hash() const override { return hash_; }

 private:
  void mix(std::uint64_t value) { hash_ = (hash_ ^ value) * 0x100000001b3ull; }
  std::uint64_t hash_ = 0xcbf29ce484222325ull;
  std::uint64_t steps_ = 0;
};

/// 300 ticks of two players, recorded as a Match records: events, inputs, a hash every 10.
Recording record(std::uint32_t skip_from = 0, std::uint32_t skip_to = 0) {
  RecordingHeader header;
  header.hash_interval_ticks = 10;
  header.tick_rate_hz = 60;
  RecordingWriter writer(header, 1 << 20);
  MixingSimulation live;
  for (std::uint32_t tick = 1; tick <= 300; ++tick) {
    std::vector<RecordedEvent> events;
    std::vector<RecordedInput> inputs;
    const bool skipped = tick >= skip_from && tick < skip_to;
    if (tick == 1) events.push_back({RecordedEventKind::Connect, 7, "seven", 0});
    if (tick == 2) events.push_back({RecordedEventKind::Connect, 8, "eight", 0});
    for (std::uint32_t id = 1; id <= (tick == 1 ? 1u : 2u) && !skipped; ++id) {
      RecordedInput input;
      input.entity_id = id;
      input.input.sequence = tick;
      input.input.yaw_rad = 0.01f * static_cast<float>(tick * id);
      input.input.buttons = tick % 7 == 0 ? proto::kButtonFire : 0u;
      inputs.push_back(input);
    }
    for (const RecordedEvent& event : events) live.apply(event);
    live.step(inputs);
    if (skipped) continue;  // a tick the recording leaves out: no events, no inputs
    writer.begin_tick(tick);
    for (const RecordedEvent& event : events) writer.add_event(event);
    for (const RecordedInput& input : inputs) writer.add_input(input);
    if (tick % 10 == 0) writer.add_hash(tick, live.state_hash());
    writer.end_tick();
  }
  auto result = read_recording(writer.finish());
  return std::get<Recording>(std::move(result));
}

TEST(ReplayTest, EveryHashMatches) {
  const Recording recording = record();
  MixingSimulation simulation;
  std::vector<std::uint32_t> seen;
  double now_s = 5;
  ReplayOptions options;
  options.wall_clock_s = [&] { return now_s += 0.25; };
  options.after_step = [&](std::uint32_t tick) { seen.push_back(tick); };
  const ReplayReport report = replay(recording, simulation, options);
  EXPECT_FALSE(report.first_mismatch.has_value());
  EXPECT_EQ(report.hashes_checked, 30u);
  EXPECT_EQ(report.steps, 300u);
  EXPECT_EQ(report.last_tick, 300u);
  EXPECT_DOUBLE_EQ(report.simulated_s, 5.0);
  EXPECT_DOUBLE_EQ(report.wall_s, 0.25);
  EXPECT_TRUE(report.complete);
  ASSERT_EQ(seen.size(), 300u);
  EXPECT_EQ(seen.front(), 1u);
  EXPECT_EQ(seen.back(), 300u);
}

TEST(ReplayTest, OneFlippedInputIsCaughtAtTheNextHash) {
  Recording recording = record();
  recording.ticks[146].inputs[1].input.buttons ^= proto::kButtonJump;  // tick 147
  MixingSimulation simulation;
  const ReplayReport report = replay(recording, simulation);
  ASSERT_TRUE(report.first_mismatch.has_value());
  EXPECT_EQ(report.first_mismatch->tick, 150u);
  EXPECT_EQ(report.last_tick, 150u) << "stops at the first mismatch";
  EXPECT_EQ(report.hashes_checked, 15u);

  MixingSimulation again;
  ReplayOptions options;
  options.stop_at_mismatch = false;
  const ReplayReport all = replay(recording, again, options);
  EXPECT_EQ(all.first_mismatch->tick, 150u);
  EXPECT_EQ(all.last_tick, 300u);
  EXPECT_EQ(all.hashes_differing, 16u) << "150 and every later hash";
}

TEST(ReplayTest, TicksTheRecordingSkipsAreSteppedEmpty) {
  const Recording recording = record(100, 120);
  ASSERT_EQ(recording.ticks.size(), 280u);
  MixingSimulation simulation;
  const ReplayReport report = replay(recording, simulation);
  EXPECT_FALSE(report.first_mismatch.has_value());
  EXPECT_EQ(report.steps, 300u);
  EXPECT_EQ(report.hashes_checked, 28u);
}

}  // namespace
}  // namespace ricochet::server::replay_test
