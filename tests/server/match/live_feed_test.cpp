// A match's live feed (live_frame.h): frames at the feed's rate of server time while someone
// watches, each what the match holds after that tick (positions, vitals, projectiles, scores),
// the kill feed complete; and watching changes nothing: the same state hash, the same bytes to
// every client and the same recording as the same match unwatched.

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "ricochet/proto/entity_flags.h"
#include "ricochet/server/live_frame.h"
#include "ricochet/server/match.h"

namespace ricochet::server::live_feed_test {
namespace {

using proto::kMicrosPerSecond;
using proto::TimeUs;

constexpr TimeUs kStart = 1'000'000;
constexpr TimeUs kTickUs = kMicrosPerSecond / 60 + 1;
constexpr int kPlayers = 4;
constexpr int kTicks = 600;

Map arena() {
  MapResult loaded = load_map_file(std::string(RICOCHET_SOURCE_DIR) + "/server/maps/arena.toml");
  if (auto* error = std::get_if<MapError>(&loaded)) ADD_FAILURE() << error->describe();
  return std::get<Map>(std::move(loaded));
}

MatchConfig fight_config() {
  MatchConfig config;
  config.id = 5;
  config.rules.min_players = 2;
  config.rules.warmup_s = 0.5f;
  config.rules.respawn_delay_s = 0.5f;
  config.rules.spawn_protection_s = 0;
  config.rules.frag_limit = 0;
  config.rules.seed = 99;
  config.weapons.weapons[0].spread_rad = 0;
  return config;
}

/// FNV-1a of every byte the match hands its clients.
struct Fnv1a {
  std::uint64_t value = 14695981039346656037ull;
  void add(std::uint8_t byte) {
    value ^= byte;
    value *= 1099511628211ull;
  }
};

/// What a frame must show, read from the match at the tick it was published.
struct Expected {
  std::vector<proto::EntityState> states;
  std::map<std::uint32_t, Match::PlayerView> views;  ///< by entity
};

struct Played {
  std::uint64_t state_hash = 0;
  std::uint64_t sent_fnv = 0;
  std::vector<std::uint8_t> recording;
  std::uint64_t kills = 0;
  std::vector<std::shared_ptr<const LiveFrame>> frames;
  std::vector<Expected> expected;  ///< one per frame
};

/// 10 s of four players fighting on the arena: each aims at the nearest other, strafes, fires
/// rifle, rockets and grenades in turn. With `feed`, a viewer watches from the start.
Played play(const std::shared_ptr<LiveFeed>& feed) {
  auto created = Match::create(fight_config(), arena(), kStart);
  EXPECT_TRUE(std::holds_alternative<Match>(created));
  Match match = std::get<Match>(std::move(created));
  std::optional<LiveFeed::Viewer> viewer;
  if (feed) {
    match.set_live_feed(feed);
    viewer = feed->watch();
    EXPECT_TRUE(viewer);
  }
  Played played;
  Fnv1a sent;
  TimeUs now = kStart;
  for (std::uint64_t account = 1; account <= kPlayers; ++account) {
    std::string name = "p";  // (not "p" + to_string: gcc 12's false -Wstringop-overflow)
    name += std::to_string(account);
    match.connect(account, name);
  }
  for (int tick = 1; tick <= kTicks; ++tick) {
    const auto states = match.entity_states();
    for (std::uint64_t account = 1; account <= kPlayers; ++account) {
      const std::uint32_t me = *match.entity_of(account);
      const proto::EntityState* self = nullptr;
      for (const auto& state : states) self = state.id == me ? &state : self;
      float yaw = 0, pitch = 0;
      double best = 1e30;
      for (const auto& state : states) {
        if (!self || state.id == me || (state.flags & proto::kEntityKindMask) != 0 ||
            (state.flags & proto::kEntityDead) != 0) {
          continue;
        }
        const double dx = state.position_m[0] - self->position_m[0];
        const double dy = state.position_m[1] - self->position_m[1];
        const double dz = state.position_m[2] - self->position_m[2];
        if (dx * dx + dy * dy + dz * dz < best) {
          best = dx * dx + dy * dy + dz * dz;
          yaw = static_cast<float>(std::atan2(-dx, -dz));
          pitch = static_cast<float>(std::atan2(dy - 0.25, std::hypot(dx, dz)));
        }
      }
      wire::ClientPayload payload;
      wire::Input& in = *payload.add_inputs();
      in.set_sequence(static_cast<std::uint32_t>(tick));
      in.set_move_right(tick / 40 % 2 == 0 ? 100 : -100);
      in.set_yaw(yaw);
      in.set_pitch(pitch);
      in.set_weapon_slot(1 + static_cast<std::uint32_t>((tick / 120 + account) % 3));
      in.set_buttons(proto::kButtonFire);
      in.set_view_tick(match.tick_number() > 4 ? match.tick_number() - 4 : 0);
      std::vector<std::uint8_t> bytes(payload.ByteSizeLong());
      payload.SerializeToArray(bytes.data(), static_cast<int>(bytes.size()));
      match.receive(account, bytes);
    }
    now += kTickUs;
    match.tick(now);
    Outgoing out;
    while (match.poll_outbox(out)) {
      for (int k = 0; k < 8; ++k) sent.add(static_cast<std::uint8_t>(out.account >> (8 * k)));
      sent.add(out.reliable ? 1 : 0);
      for (const std::uint8_t byte : out.bytes) sent.add(byte);
    }
    if (viewer) {
      std::shared_ptr<const LiveFrame> frame = viewer->latest();
      if (frame && (played.frames.empty() || frame != played.frames.back())) {
        Expected expected;
        expected.states.assign(match.entity_states().begin(), match.entity_states().end());
        for (std::uint64_t account = 1; account <= kPlayers; ++account) {
          expected.views.emplace(*match.entity_of(account), *match.player_view(account));
        }
        played.frames.push_back(std::move(frame));
        played.expected.push_back(std::move(expected));
      }
    }
  }
  played.state_hash = match.state_hash();
  played.sent_fnv = sent.value;
  played.kills = match.counters().kills;
  played.recording = match.take_recording();
  return played;
}

TEST(LiveFeed, WatchingChangesNoStateNoSnapshotAndNoRecording) {
  const Played unwatched = play(nullptr);
  const Played watched = play(std::make_shared<LiveFeed>(LiveFeedConfig{}));
  EXPECT_GT(unwatched.kills, 3u);  // the fight is a fight: kills, so the kill notes ran
  ASSERT_FALSE(watched.frames.empty());
  EXPECT_EQ(watched.state_hash, unwatched.state_hash);
  EXPECT_EQ(watched.sent_fnv, unwatched.sent_fnv);
  EXPECT_TRUE(watched.recording == unwatched.recording);  // (bytes: not printed)
  EXPECT_EQ(watched.kills, unwatched.kills);
}

TEST(LiveFeed, FramesComeAtTheFeedRateWithWhatTheMatchHolds) {
  const Played played = play(std::make_shared<LiveFeed>(LiveFeedConfig{}));
  // 60 Hz ticks, 20 Hz frames: one every third tick (a tick is 1 µs over 1/60 s here).
  ASSERT_GE(played.frames.size(), static_cast<std::size_t>(kTicks / 3 - 1));
  ASSERT_LE(played.frames.size(), static_cast<std::size_t>(kTicks / 3 + 1));
  std::uint64_t kills_shown = 0;
  bool saw_rocket = false, saw_grenade = false;
  for (std::size_t f = 0; f < played.frames.size(); ++f) {
    const LiveFrame& frame = *played.frames[f];
    const Expected& expected = played.expected[f];
    EXPECT_EQ(frame.match_id, 5u);
    EXPECT_EQ(frame.tick_rate_hz, 60);
    EXPECT_EQ(frame.server_time_us, kStart + static_cast<TimeUs>(frame.tick) * kTickUs);
    if (f > 0) {
      const LiveFrame& before = *played.frames[f - 1];
      EXPECT_EQ(frame.tick - before.tick, 3u) << "frame " << f;
      EXPECT_GE(frame.server_time_us - before.server_time_us, 50'000);
    }
    ASSERT_EQ(frame.players.size(), static_cast<std::size_t>(kPlayers));
    std::size_t projectiles = 0;
    for (const proto::EntityState& state : expected.states) {
      const auto kind = state.flags & proto::kEntityKindMask;
      if (kind == 0) {
        const auto player =
            std::find_if(frame.players.begin(), frame.players.end(),
                         [&](const LivePlayer& p) { return p.entity_id == state.id; });
        ASSERT_NE(player, frame.players.end());
        EXPECT_EQ(player->position_m, state.position_m);
        EXPECT_EQ(player->velocity_mps, state.velocity_mps);
        EXPECT_EQ(player->alive, (state.flags & proto::kEntityDead) == 0);
        const Match::PlayerView& view = expected.views.at(state.id);
        EXPECT_EQ(player->health, view.vitals.health);
        EXPECT_EQ(player->armor, view.vitals.armor);
        EXPECT_EQ(player->weapon, view.weapon);
        continue;
      }
      ASSERT_LT(projectiles, frame.projectiles.size());
      const LiveProjectile& shot = frame.projectiles[projectiles++];
      EXPECT_EQ(shot.entity_id, state.id);
      EXPECT_EQ(shot.position_m, state.position_m);
      const bool grenade = kind == proto::kind_flags(proto::EntityKind::Grenade);
      EXPECT_EQ(shot.kind, grenade ? LiveProjectileKind::Grenade : LiveProjectileKind::Rocket);
      saw_grenade |= grenade;
      saw_rocket |= !grenade;
    }
    EXPECT_EQ(projectiles, frame.projectiles.size());
    for (const LiveKill& kill : frame.kills) {
      EXPECT_LE(kill.tick, frame.tick);
      if (f > 0) {
        EXPECT_GT(kill.tick, played.frames[f - 1]->tick);
      }
    }
    EXPECT_EQ(frame.kills_dropped, 0u);
    kills_shown += frame.kills.size();
  }
  EXPECT_TRUE(saw_rocket);
  EXPECT_TRUE(saw_grenade);
  // Every death reached the kill feed (the last frame is at most two ticks before the end).
  EXPECT_GE(kills_shown + 2, played.kills);
  EXPECT_LE(kills_shown, played.kills);
  EXPECT_GT(kills_shown, 0u);
  // The scoreboard: the last frame's kills add up to the kills it has shown while running.
  int scored = 0;
  for (const LivePlayer& player : played.frames.back()->players) scored += player.kills;
  EXPECT_GT(scored, 0);
  EXPECT_EQ(played.frames.back()->phase, MatchPhase::Running);
  EXPECT_TRUE(played.frames.back()->time_left_s);
}

/// Two players in the fight's match, with a time limit of `time_limit_s` of running (0: none).
Match two_player_match(float time_limit_s) {
  MatchConfig config = fight_config();
  config.rules.time_limit_s = time_limit_s;
  auto created = Match::create(config, arena(), kStart);
  EXPECT_TRUE(std::holds_alternative<Match>(created));
  Match match = std::get<Match>(std::move(created));
  match.connect(1, "ann");
  match.connect(2, "bob");
  return match;
}

TEST(LiveFeed, AMatchReachingItsEndShowsTheEndedPhaseAtOnce) {
  Match match = two_player_match(1.0f);
  // A frame a second: the end (0.5 s of warm-up, 1 s of running) falls between two.
  auto feed = std::make_shared<LiveFeed>(LiveFeedConfig{1, 8});
  match.set_live_feed(feed);
  std::optional<LiveFeed::Viewer> viewer = feed->watch();
  TimeUs now = kStart;
  for (int k = 0; k < 300 && !match.ended(); ++k) match.tick(now += kTickUs);
  ASSERT_TRUE(match.ended());
  const std::shared_ptr<const LiveFrame> frame = viewer->latest();
  ASSERT_TRUE(frame);
  EXPECT_EQ(frame->phase, MatchPhase::Ended);
  EXPECT_EQ(frame->tick, match.tick_number());
  EXPECT_EQ(frame->server_time_us, now);
  EXPECT_FALSE(frame->time_left_s);
  EXPECT_EQ(frame->players.size(), 2u);
  // It is the last one.
  for (int k = 0; k < 120; ++k) match.tick(now += kTickUs);
  EXPECT_EQ(viewer->latest(), frame);
}

TEST(LiveFeed, AMatchStoppedByEndShowsTheEndedPhase) {
  Match match = two_player_match(0);
  auto feed = std::make_shared<LiveFeed>(LiveFeedConfig{});
  match.set_live_feed(feed);
  std::optional<LiveFeed::Viewer> viewer = feed->watch();
  TimeUs now = kStart;
  for (int k = 0; k < 61; ++k) match.tick(now += kTickUs);
  const std::shared_ptr<const LiveFrame> running = viewer->latest();
  ASSERT_TRUE(running);
  ASSERT_EQ(running->phase, MatchPhase::Running);
  match.tick(now += kTickUs);  // a tick with no frame due (one every third)
  ASSERT_EQ(viewer->latest(), running);
  match.end(wire::MATCH_END_REASON_SERVER_SHUTDOWN);
  const std::shared_ptr<const LiveFrame> ended = viewer->latest();
  ASSERT_NE(ended, running);
  EXPECT_EQ(ended->phase, MatchPhase::Ended);
  EXPECT_EQ(ended->tick, match.tick_number());
  EXPECT_EQ(ended->server_time_us, now);  // the last step's time
  EXPECT_EQ(ended->players.size(), 2u);
  match.end(wire::MATCH_END_REASON_SERVER_SHUTDOWN);
  match.tick(now += kTickUs * 10);
  EXPECT_EQ(viewer->latest(), ended);
}

TEST(LiveFeed, NoFrameIsBuiltWhileNobodyWatches) {
  auto created = Match::create(fight_config(), arena(), kStart);
  ASSERT_TRUE(std::holds_alternative<Match>(created));
  Match match = std::get<Match>(std::move(created));
  auto feed = std::make_shared<LiveFeed>(LiveFeedConfig{});
  match.set_live_feed(feed);
  match.connect(1, "ann");
  TimeUs now = kStart;
  for (int k = 0; k < 10; ++k) match.tick(now += kTickUs);
  EXPECT_EQ(feed->latest(), nullptr);
  std::optional<LiveFeed::Viewer> viewer = feed->watch();
  match.tick(now += kTickUs);  // the first frame comes at the next tick
  ASSERT_TRUE(viewer->latest());
  EXPECT_EQ(viewer->latest()->tick, match.tick_number());
  viewer.reset();
  match.tick(now += kTickUs);
  EXPECT_EQ(feed->latest(), nullptr);
  match.set_live_feed(nullptr);
  viewer = feed->watch();
  match.tick(now += kTickUs);
  EXPECT_EQ(viewer->latest(), nullptr);  // detached
}

}  // namespace
}  // namespace ricochet::server::live_feed_test
