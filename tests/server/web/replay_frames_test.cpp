// A recording re-simulated into frames (replay_frames.h): every tick's positions are the floats
// ricochet-replay's engine gives (checked against a replay of our own, bit for bit, and printed
// as --export prints them), the kill feed is the replayed match's, a mismatch is the verdict,
// and the frames stay within their memory budget.

#include "replay_frames.h"

#include <gtest/gtest.h>

#include <bit>
#include <cstdio>
#include <string>
#include <variant>
#include <vector>

#include "ricochet/server/match_replay.h"
#include "scripted_recording.h"

namespace ricochet::server::replay_frames_test {
namespace {

Recording read(const std::vector<std::uint8_t>& bytes) {
  auto read = read_recording(bytes);
  EXPECT_TRUE(std::holds_alternative<Recording>(read));
  return std::get<Recording>(std::move(read));
}

/// ricochet-replay's own loop (tools/replay/main.cpp): every step's entity states, by tick.
struct Reference {
  std::vector<std::vector<proto::EntityState>> states{{}};  // [tick], [0] empty
  std::uint64_t kills = 0;
  ReplayReport report;
};
Reference replay_as_the_tool_does(const Recording& recording) {
  Reference reference;
  auto opened = open_recorded_match(recording);
  EXPECT_TRUE(std::holds_alternative<Match>(opened));
  Match& match = std::get<Match>(opened);
  MatchSimulation simulation(match);
  ReplayOptions options;
  options.after_step = [&](std::uint32_t) {
    const auto states = match.entity_states();
    reference.states.emplace_back(states.begin(), states.end());
  };
  reference.report = replay(recording, simulation, options);
  reference.kills = match.counters().kills;
  return reference;
}

std::string export_text(float value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.9g", static_cast<double>(value));
  return text;
}

TEST(ReplayFramesTest, EveryTickHoldsTheReplayedStatesAndTheKillsOfTheReplayedMatch) {
  const Recording recording = read(web_test::scripted_recording());
  const Reference reference = replay_as_the_tool_does(recording);
  ReplayProgress progress;
  auto run = replay_frames(recording, progress, 64u << 20);
  ASSERT_TRUE(std::holds_alternative<ReplayFrames>(run)) << std::get<std::string>(run);
  const ReplayFrames& frames = std::get<ReplayFrames>(run);

  ASSERT_EQ(frames.last_tick, reference.report.last_tick);
  EXPECT_EQ(progress.ticks_done.load(), frames.last_tick);
  EXPECT_FALSE(frames.report.first_mismatch.has_value());
  EXPECT_GT(frames.report.hashes_checked, 20u);
  std::size_t players = 0, projectiles = 0;
  for (std::uint32_t tick = 1; tick <= frames.last_tick; ++tick) {
    const auto& want = reference.states[tick];
    ASSERT_EQ(frames.tick_start[tick] - frames.tick_start[tick - 1], want.size()) << tick;
    for (std::size_t i = 0; i < want.size(); ++i) {
      const FrameEntity& got = frames.entities[frames.tick_start[tick - 1] + i];
      EXPECT_EQ(got.id, want[i].id);
      EXPECT_EQ(got.flags, want[i].flags);
      for (int axis = 0; axis < 3; ++axis) {
        EXPECT_EQ(std::bit_cast<std::uint32_t>(got.position_m[axis]),
                  std::bit_cast<std::uint32_t>(want[i].position_m[axis]))
            << "tick " << tick << " entity " << got.id;
      }
      const bool player = (got.flags & proto::kEntityKindMask) == 0;
      (player ? players : projectiles) += 1;
      if (player && !(got.flags & proto::kEntityDead)) {
        EXPECT_GT(got.health, 0);
      }
    }
  }
  EXPECT_GT(players, 3000u);
  EXPECT_GT(projectiles, 0u) << "the script fires rockets";

  // The kill feed: every kill the replayed match counted, each in the frame of its tick.
  EXPECT_GT(reference.kills, 0u) << "the script makes the players kill each other";
  EXPECT_EQ(frames.kills.size(), reference.kills);
  for (const FrameKill& k : frames.kills) {
    EXPECT_TRUE(k.event_tick == k.tick || k.event_tick + 1 == k.tick) << k.tick;
    bool dead = false;  // the frame of the kill's step shows the victim dead
    for (std::uint32_t i = frames.tick_start[k.tick - 1]; i < frames.tick_start[k.tick]; ++i) {
      const FrameEntity& e = frames.entities[i];
      if (e.id == k.victim) dead = (e.flags & proto::kEntityDead) != 0 && e.health <= 0;
    }
    EXPECT_TRUE(dead) << "kill of " << k.victim << " at tick " << k.tick;
  }
  ASSERT_EQ(frames.players.size(), 4u);
  int deaths = 0;
  for (const FrameScore& score : frames.scores) deaths = std::max(deaths, score.deaths);
  EXPECT_GT(deaths, 0);

  // The document a viewer asks for: positions as --export prints them, kills in their tick.
  ASSERT_FALSE(frames.kills.empty());
  const FrameKill& kill = frames.kills.front();
  std::string error;
  const std::string json = frames_json(frames, kill.tick, kill.tick + 2, error);
  ASSERT_EQ(error, "");
  const proto::EntityState& first = reference.states[kill.tick].front();
  EXPECT_NE(json.find("{\"id\":" + std::to_string(first.id) +
                      ",\"x\":" + export_text(first.position_m[0]) +
                      ",\"y\":" + export_text(first.position_m[1]) +
                      ",\"z\":" + export_text(first.position_m[2]) + ","),
            std::string::npos)
      << json;
  EXPECT_NE(json.find("\"kills\":[{\"killer\":" + std::to_string(kill.killer) +
                      ",\"victim\":" + std::to_string(kill.victim)),
            std::string::npos)
      << json;
  EXPECT_NE(replay_summary_json(frames).find("\"hashes_matched\":true"), std::string::npos);
}

TEST(ReplayFramesTest, ARangeOutsideTheReplayOrTooLongIsRefused) {
  const Recording recording = read(web_test::scripted_recording(120));
  ReplayProgress progress;
  auto run = replay_frames(recording, progress, 16u << 20);
  ASSERT_TRUE(std::holds_alternative<ReplayFrames>(run));
  const ReplayFrames& frames = std::get<ReplayFrames>(run);
  std::string error;
  for (const auto& [first, end] : std::vector<std::pair<std::uint32_t, std::uint32_t>>{
           {0, 5}, {5, 5}, {6, 5}, {1, frames.last_tick + 2}, {4'000'000'000u, 4'000'000'001u}}) {
    EXPECT_EQ(frames_json(frames, first, end, error), "");
    EXPECT_NE(error.find("must be within 1.." + std::to_string(frames.last_tick + 1)),
              std::string::npos)
        << first << " " << end;
  }
  EXPECT_NE(frames_json(frames, 1, frames.last_tick + 1, error), "");
  EXPECT_EQ(error, "");
  const Recording longer = read(web_test::scripted_recording(kMaxFramesPerRequest + 10));
  auto long_run = replay_frames(longer, progress, 16u << 20);
  ASSERT_TRUE(std::holds_alternative<ReplayFrames>(long_run));
  EXPECT_EQ(frames_json(std::get<ReplayFrames>(long_run), 1, kMaxFramesPerRequest + 2, error), "");
  EXPECT_NE(error.find("at most 600"), std::string::npos) << error;
}

TEST(ReplayFramesTest, AFlippedInputIsTheVerdictAndTheFramesStopThere) {
  Recording recording = read(web_test::scripted_recording(300));
  RecordedTick& tick = recording.ticks.at(100);
  ASSERT_FALSE(tick.inputs.empty());
  tick.inputs[0].input.move_right = -tick.inputs[0].input.move_right;
  ReplayProgress progress;
  auto run = replay_frames(recording, progress, 16u << 20);
  ASSERT_TRUE(std::holds_alternative<ReplayFrames>(run));
  const ReplayFrames& frames = std::get<ReplayFrames>(run);
  ASSERT_TRUE(frames.report.first_mismatch.has_value());
  EXPECT_GE(frames.report.first_mismatch->tick, tick.tick);
  EXPECT_EQ(frames.last_tick, frames.report.first_mismatch->tick);
  EXPECT_NE(replay_summary_json(frames).find("\"hashes_matched\":false,\"first_mismatch_tick\":" +
                                             std::to_string(frames.report.first_mismatch->tick)),
            std::string::npos);
}

TEST(ReplayFramesTest, FramesOverTheBudgetOrAStopEndTheRunWithWhy) {
  const Recording recording = read(web_test::scripted_recording(300));
  ReplayProgress progress;
  auto small = replay_frames(recording, progress, 8 * 1024);
  ASSERT_TRUE(std::holds_alternative<std::string>(small));
  EXPECT_NE(std::get<std::string>(small).find("the replay needs more than 8192 bytes"),
            std::string::npos)
      << std::get<std::string>(small);
  EXPECT_LT(progress.ticks_done.load(), 300u);

  ReplayProgress stopped;
  stopped.stop = true;
  auto run = replay_frames(recording, stopped, 16u << 20);
  ASSERT_TRUE(std::holds_alternative<std::string>(run));
  EXPECT_EQ(std::get<std::string>(run), "stopped");
  EXPECT_EQ(stopped.ticks_done.load(), 1u) << "stops after the step it was asked at";
}

}  // namespace
}  // namespace ricochet::server::replay_frames_test
