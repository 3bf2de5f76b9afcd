// A match records itself (recording.h) and plays back bit for bit: a scripted fight with joins,
// a disconnect and a return, a leave, rifles, rockets and grenades; every recorded hash matches
// in playback, and one flipped input is caught at the first hash after it.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "ricochet/server/match.h"
#include "ricochet/server/match_record.h"
#include "ricochet/server/recording.h"

namespace ricochet::server::match_recording_test {
namespace {

using proto::kMicrosPerSecond;
using proto::TimeUs;

constexpr TimeUs kStart = 1'000'000;
constexpr TimeUs kTickUs = kMicrosPerSecond / 60 + 1;

Map arena() {
  Map map;
  map.name = "recorded";
  map.bounds_min_m = physics::Vec3(-20, -5, -20);
  map.bounds_max_m = physics::Vec3(20, 15, 20);
  map.floor_y_m = 0.0f;
  map.boxes.push_back(MapBox{physics::Vec3(4, 1, 0), physics::Vec3(1, 1, 1), 0.3f});
  for (int k = 0; k < 6; ++k) {
    const float angle = static_cast<float>(k) * std::numbers::pi_v<float> / 3;
    map.spawns.push_back(
        MapSpawn{physics::Vec3(8 * std::cos(angle), 0.4f, 8 * std::sin(angle)), angle, Team::None});
  }
  map.pickups.push_back(MapPickup{PickupKind::Armor, physics::Vec3(0, 0.4f, 0), 50, 3.0f});
  map.files.push_back(MapFile{"recorded.toml", "(built in the test)"});
  return map;
}

MatchConfig recorded_config() {
  MatchConfig config;
  config.rules.min_players = 2;
  config.rules.warmup_s = 0.5f;
  config.rules.respawn_delay_s = 0.5f;
  config.rules.frag_limit = 0;
  config.rules.seed = 77;
  config.weapons.weapons[0].spread_rad = 0.03f;
  config.hash_interval_ticks = 10;
  return config;
}

/// Plays 20 s of a scripted four-player fight and returns the finished recording; `counted`
/// gets who counts in its record.
std::vector<std::uint8_t> play_scripted_match(std::uint64_t* final_hash,
                                              std::vector<CountedPlayer>* counted = nullptr) {
  auto created = Match::create(recorded_config(), arena(), kStart);
  EXPECT_TRUE(std::holds_alternative<Match>(created));
  Match match = std::get<Match>(std::move(created));
  TimeUs now = kStart;
  std::uint32_t sequence[5] = {};
  for (int tick = 0; tick < 1200; ++tick) {
    if (tick == 0) match.connect(1, "ann");
    if (tick == 5) match.connect(2, "ben");
    if (tick == 30) match.connect(3, "cid");
    if (tick == 200) match.disconnect(2, now);
    if (tick == 260) match.connect(2, "ben");  // back within the grace
    if (tick == 400) match.connect(4, "dee");
    if (tick == 800) match.leave(3);
    for (std::uint64_t account = 1; account <= 4; ++account) {
      if (!match.entity_of(account) || (account == 2 && tick >= 200 && tick < 260)) continue;
      wire::ClientPayload payload;
      wire::Input& in = *payload.add_inputs();
      in.set_sequence(++sequence[account]);
      const double t = tick / 60.0;
      in.set_move_forward(static_cast<int>(127 * std::sin(t + account)));
      in.set_move_right(static_cast<int>(127 * std::cos(0.7 * t * account)));
      in.set_yaw(static_cast<float>(std::fmod(0.8 * t * account, 6.0)));
      in.set_pitch(static_cast<float>(-0.2 + 0.1 * std::sin(t)));
      in.set_weapon_slot(1 + static_cast<std::uint32_t>((tick / 90 + account) % 3));
      in.set_buttons((tick % 4 < 2 ? proto::kButtonFire : 0u) |
                     (tick % 97 == 0 ? proto::kButtonJump : 0u));
      in.set_view_tick(match.tick_number() > 4 ? match.tick_number() - 4 : 0);
      std::vector<std::uint8_t> bytes(payload.ByteSizeLong());
      payload.SerializeToArray(bytes.data(), static_cast<int>(bytes.size()));
      match.receive(account, bytes);
      match.set_latency(account, 20'000 + 5'000 * static_cast<TimeUs>(account));
    }
    now += kTickUs;
    match.tick(now);
    Outgoing out;
    while (match.poll_outbox(out)) {
    }
  }
  EXPECT_GT(match.counters().shots_fired, 100u);
  EXPECT_GT(match.counters().explosions, 5u);
  EXPECT_FALSE(match.counters().recording_truncated);
  if (final_hash) *final_hash = match.state_hash();
  if (counted) *counted = counted_players(match.scoreboard(), match.config().tick.rate_hz);
  return match.take_recording();
}

/// Plays a recording back into a fresh match; returns the first tick whose recorded hash
/// differs (0: all matched) and counts the hashes checked.
std::uint32_t play_back(const Recording& recording, int& checked, std::uint64_t* final_hash,
                        std::vector<CountedPlayer>* counted = nullptr) {
  auto config = decode_match_config(recording.header.config);
  EXPECT_TRUE(std::holds_alternative<MatchConfig>(config));
  MatchConfig replay_config = std::get<MatchConfig>(config);
  replay_config.record = false;
  auto created = Match::create(replay_config, arena(), 0);
  EXPECT_TRUE(std::holds_alternative<Match>(created));
  Match match = std::get<Match>(std::move(created));
  std::size_t next_hash = 0;
  checked = 0;
  for (const RecordedTick& tick : recording.ticks) {
    for (const RecordedEvent& event : tick.events) match.apply(event);
    match.step_recorded(tick.inputs);
    EXPECT_EQ(match.tick_number(), tick.tick);
    while (next_hash < recording.hashes.size() && recording.hashes[next_hash].tick == tick.tick) {
      ++checked;
      if (recording.hashes[next_hash].hash != match.state_hash()) return tick.tick;
      ++next_hash;
    }
  }
  if (final_hash) *final_hash = match.state_hash();
  if (counted) *counted = counted_players(match.scoreboard(), match.config().tick.rate_hz);
  return 0;
}

TEST(MatchRecording, AScriptedMatchPlaysBackBitForBit) {
  std::uint64_t live_hash = 0;
  const std::vector<std::uint8_t> bytes = play_scripted_match(&live_hash);
  auto read = read_recording(bytes);
  ASSERT_TRUE(std::holds_alternative<Recording>(read)) << std::get<RecordingError>(read).message;
  const Recording& recording = std::get<Recording>(read);
  EXPECT_TRUE(recording.complete);
  ASSERT_EQ(recording.ticks.size(), 1200u);
  int checked = 0;
  std::uint64_t replay_hash = 0;
  EXPECT_EQ(play_back(recording, checked, &replay_hash), 0u);
  EXPECT_GE(checked, 120);
  EXPECT_EQ(replay_hash, live_hash);
  // Bytes per player-minute, for the record: 4 players (at most) for 20 s.
  RecordProperty("bytes", static_cast<int>(bytes.size()));
}

TEST(MatchRecording, ThePlaybackCountsTheSamePlayersForTheSameTime) {
  std::vector<CountedPlayer> live;
  const std::vector<std::uint8_t> bytes = play_scripted_match(nullptr, &live);
  auto read = read_recording(bytes);
  ASSERT_TRUE(std::holds_alternative<Recording>(read)) << std::get<RecordingError>(read).message;
  int checked = 0;
  std::vector<CountedPlayer> replayed;
  ASSERT_EQ(play_back(std::get<Recording>(read), checked, nullptr, &replayed), 0u);
  ASSERT_EQ(live.size(), 4u);  // cid left, and still counts
  ASSERT_EQ(replayed.size(), live.size());
  for (std::size_t k = 0; k < live.size(); ++k) {
    EXPECT_EQ(replayed[k].score.account, live[k].score.account);
    EXPECT_EQ(replayed[k].score.ticks_played, live[k].score.ticks_played);
    EXPECT_EQ(replayed[k].score.kills, live[k].score.kills);
    EXPECT_EQ(replayed[k].score.deaths, live[k].score.deaths);
    EXPECT_EQ(replayed[k].seconds_played, live[k].seconds_played);
    EXPECT_GT(live[k].seconds_played, 0) << live[k].score.name;
  }
}

TEST(MatchRecording, OneFlippedInputIsCaughtAtTheNextHash) {
  const std::vector<std::uint8_t> bytes = play_scripted_match(nullptr);
  auto read = read_recording(bytes);
  ASSERT_TRUE(std::holds_alternative<Recording>(read));
  Recording recording = std::get<Recording>(std::move(read));
  // Ann's aim at step 503 turns a little: the world diverges from there on.
  RecordedTick& tick = recording.ticks[502];
  ASSERT_EQ(tick.tick, 503u);
  ASSERT_FALSE(tick.inputs.empty());
  tick.inputs[0].input.yaw_rad += 0.3f;
  tick.inputs[0].input.buttons |= proto::kButtonFire;
  int checked = 0;
  const std::uint32_t first_bad = play_back(recording, checked, nullptr);
  EXPECT_EQ(first_bad, 510u);  // the first hash at or after 503 (every 10 ticks)
}

TEST(MatchConfigCodec, RoundTripsExactlyAndRefusesBadText) {
  MatchConfig config = recorded_config();
  config.weapons.weapons[1].projectile_speed_mps = 31.4159f;
  config.rules.mode = GameMode::TeamDeathmatch;
  config.name = "a name with spaces";
  const std::vector<std::uint8_t> bytes = encode_match_config(config);
  auto decoded = decode_match_config(bytes);
  ASSERT_TRUE(std::holds_alternative<MatchConfig>(decoded)) << std::get<std::string>(decoded);
  EXPECT_EQ(encode_match_config(std::get<MatchConfig>(decoded)), bytes);
  EXPECT_EQ(std::get<MatchConfig>(decoded).weapons.weapons[1].projectile_speed_mps, 31.4159f);

  std::string text(bytes.begin(), bytes.end());
  const auto refuse = [](const std::string& bad) {
    const std::vector<std::uint8_t> b(bad.begin(), bad.end());
    return std::holds_alternative<std::string>(decode_match_config(b));
  };
  EXPECT_TRUE(refuse(""));
  EXPECT_TRUE(refuse(text + "unknown_key 1\n"));
  EXPECT_TRUE(refuse(text.substr(0, text.size() / 2)));
  std::string wrong = text;
  wrong.replace(wrong.find("max_players 16"), 14, "max_players 99");
  EXPECT_TRUE(refuse(wrong));  // out of range after decoding
  std::string nan = text;
  const std::size_t at = nan.find("movement.friction ");
  nan.replace(at, nan.find('\n', at) - at, "movement.friction nan");
  EXPECT_TRUE(refuse(nan));
}

}  // namespace
}  // namespace ricochet::server::match_recording_test
