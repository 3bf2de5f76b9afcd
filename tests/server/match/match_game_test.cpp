// The game rules of a match, with fake time and scripted inputs: the lifecycle, the rifle with
// lag compensation, rockets and grenades, damage, armour, deaths and respawns, spawn
// protection, teams, pickups, kill volumes, the limits, the input checks, determinism.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "ricochet/proto/entity_flags.h"
#include "ricochet/server/match.h"

namespace ricochet::server::match_game_test {
namespace {

using proto::kMicrosPerSecond;
using proto::TimeUs;

constexpr TimeUs kStart = 1'000'000;
constexpr TimeUs kTickUs = kMicrosPerSecond / 60 + 1;  // a little over one 60 Hz period

/// A 40 × 40 m floor with two spawns 10 m apart facing each other along z.
Map duel_map() {
  Map map;
  map.name = "duel";
  map.bounds_min_m = physics::Vec3(-20, -5, -20);
  map.bounds_max_m = physics::Vec3(20, 15, 20);
  map.floor_y_m = 0.0f;
  map.spawns.push_back(MapSpawn{physics::Vec3(0, 0.4f, 5), 0.0f, Team::None});
  map.spawns.push_back(MapSpawn{physics::Vec3(0, 0.4f, -5), std::numbers::pi_v<float>, Team::None});
  return map;
}

/// The yaw that looks from `from` towards `to` (yaw 0 looks along -Z, counter-clockwise).
float yaw_towards(const physics::Vec3& from, const physics::Vec3& to) {
  const physics::Vec3 d = to - from;
  return static_cast<float>(std::atan2(-d.x(), -d.z()));
}

float pitch_towards(const physics::Vec3& from, const physics::Vec3& to) {
  const physics::Vec3 d = to - from;
  return static_cast<float>(std::atan2(d.y(), std::hypot(d.x(), d.z())));
}

MatchConfig quick_config() {
  MatchConfig config;
  config.rules.min_players = 1;
  config.rules.warmup_s = 0;
  config.rules.spawn_protection_s = 0;
  config.rules.respawn_delay_s = 1;
  config.weapons.weapons[0].spread_rad = 0;
  return config;
}

/// One scripted client: the input it holds, sent every tick with a growing sequence.
struct Script {
  std::uint64_t account = 0;
  std::uint32_t entity = 0;
  std::uint32_t sequence = 0;
  wire::Input input;
};

class GameFixture : public ::testing::Test {
 protected:
  void start(const MatchConfig& config = quick_config(), const Map& map = duel_map()) {
    auto created = Match::create(config, map, kStart);
    ASSERT_TRUE(std::holds_alternative<Match>(created)) << std::get<std::string>(created);
    match_.emplace(std::get<Match>(std::move(created)));
  }
  Match& match() { return *match_; }

  Script& join(std::uint64_t account, const std::string& name) {
    auto joined = match().connect(account, name);
    EXPECT_TRUE(std::holds_alternative<Joined>(joined));
    Script& script = scripts_[account];
    script.account = account;
    script.entity = std::get<Joined>(joined).entity_id;
    drain();
    return script;
  }

  /// `count` steps, each with every script's current input.
  void step(int count = 1) {
    for (int k = 0; k < count; ++k) {
      for (auto& [account, script] : scripts_) {
        if (!match().entity_of(account)) continue;
        wire::ClientPayload payload;
        wire::Input& in = *payload.add_inputs();
        in = script.input;
        in.set_sequence(++script.sequence);
        std::vector<std::uint8_t> bytes(payload.ByteSizeLong());
        payload.SerializeToArray(bytes.data(), static_cast<int>(bytes.size()));
        match().receive(account, bytes);
      }
      now_ += kTickUs;
      match().tick(now_);
      drain();
    }
  }

  void drain() {
    Outgoing out;
    while (match().poll_outbox(out)) {
      if (!out.reliable) continue;
      wire::GameEvent event;
      ASSERT_TRUE(event.ParseFromArray(out.bytes.data(), static_cast<int>(out.bytes.size())));
      events_[out.account].push_back(event);
    }
  }

  physics::Vec3 position(std::uint32_t entity) {
    for (const proto::EntityState& state : match().entity_states()) {
      if (state.id == entity) {
        return physics::Vec3(state.position_m[0], state.position_m[1], state.position_m[2]);
      }
    }
    ADD_FAILURE() << "no entity " << entity;
    return physics::Vec3::Zero();
  }

  /// Points `shooter` at `point` (from its eye). A turn larger than the turn-rate check allows
  /// in one tick (1 rad at 60 Hz) is given four ticks to complete, as a person would take.
  void aim_at(Script& shooter, const physics::Vec3& point) {
    const physics::Vec3 eye = eye_position(position(shooter.entity));
    const float yaw = yaw_towards(eye, point);
    const float pitch = pitch_towards(eye, point);
    const float turn =
        std::abs(std::remainder(yaw - shooter.input.yaw(), 2 * std::numbers::pi_v<float>));
    const bool large = turn > 0.9f || std::abs(pitch - shooter.input.pitch()) > 0.9f;
    shooter.input.set_yaw(yaw);
    shooter.input.set_pitch(pitch);
    if (large) step(4);
  }
  /// Points `shooter` at the centre of `target`.
  void aim(Script& shooter, std::uint32_t target) { aim_at(shooter, position(target)); }

  int health(std::uint64_t account) { return match().player_view(account)->vitals.health; }

  PlayerScore score_of(std::uint64_t account) {
    for (const PlayerScore& score : match().scoreboard()) {
      if (score.account == account) return score;
    }
    ADD_FAILURE() << "no score for " << account;
    return {};
  }

  template <typename Predicate>
  int count_events(std::uint64_t account, Predicate predicate) {
    int n = 0;
    for (const wire::GameEvent& event : events_[account]) n += predicate(event) ? 1 : 0;
    return n;
  }

  std::optional<Match> match_;
  TimeUs now_ = kStart;
  std::map<std::uint64_t, Script> scripts_;
  std::map<std::uint64_t, std::vector<wire::GameEvent>> events_;
};

// --- lifecycle ---

TEST_F(GameFixture, WaitsForPlayersThenWarmsUpThenRuns) {
  MatchConfig config = quick_config();
  config.rules.min_players = 2;
  config.rules.warmup_s = 1;
  start(config);
  join(1, "alice");
  step(10);
  EXPECT_EQ(match().phase(), MatchPhase::Waiting);
  join(2, "bob");
  step(1);
  EXPECT_EQ(match().phase(), MatchPhase::Warmup);
  // Bob leaves during the warmup: back to waiting.
  match().leave(2);
  scripts_.erase(2);
  step(1);
  EXPECT_EQ(match().phase(), MatchPhase::Waiting);
  join(3, "carol");
  step(1);
  EXPECT_EQ(match().phase(), MatchPhase::Warmup);
  step(60);
  EXPECT_EQ(match().phase(), MatchPhase::Running);
  const int states = count_events(1, [](const wire::GameEvent& e) {
    return e.has_match_state() && e.match_state().phase() == wire::MATCH_PHASE_RUNNING;
  });
  EXPECT_EQ(states, 1);
}

TEST_F(GameFixture, TimeLimitEndsTheMatch) {
  MatchConfig config = quick_config();
  config.rules.time_limit_s = 2;
  start(config);
  join(1, "alice");
  step(1);
  ASSERT_EQ(match().phase(), MatchPhase::Running);
  step(118);
  EXPECT_FALSE(match().ended());
  step(2);
  EXPECT_TRUE(match().ended());
  EXPECT_EQ(match().end_reason(), wire::MATCH_END_REASON_TIME_LIMIT);
  EXPECT_EQ(count_events(1, [](const wire::GameEvent& e) { return e.has_match_ended(); }), 1);
  EXPECT_TRUE(std::holds_alternative<JoinRefusal>(match().connect(9, "late")));
}

// --- the rifle, damage, death, respawn ---

TEST_F(GameFixture, RifleKillsInFiveHitsAndTheVictimRespawnsAwayFromTheKiller) {
  start();
  Script& alice = join(1, "alice");
  Script& bob = join(2, "bob");
  step(30);  // both settle on the floor
  aim(alice, bob.entity);
  alice.input.set_buttons(proto::kButtonFire);
  step(1);
  EXPECT_EQ(health(2), 80);
  EXPECT_EQ(score_of(1).shots, 1);
  EXPECT_EQ(score_of(1).hits, 1);
  step(60);  // 0.1 s between shots: four more hits kill
  EXPECT_FALSE(match().player_view(2)->alive);
  EXPECT_EQ(score_of(1).kills, 1);
  EXPECT_EQ(score_of(1).score, 1);
  EXPECT_EQ(score_of(2).deaths, 1);
  EXPECT_EQ(score_of(1).damage_dealt, 100);
  EXPECT_EQ(score_of(2).damage_taken, 100);
  EXPECT_EQ(count_events(1,
                         [&](const wire::GameEvent& e) {
                           return e.has_kill() && e.kill().killer_entity_id() == alice.entity &&
                                  e.kill().victim_entity_id() == bob.entity &&
                                  e.kill().weapon() == wire::WEAPON_RIFLE;
                         }),
            1);
  alice.input.set_buttons(0);
  const auto spawned = [&](const wire::GameEvent& e) {
    return e.has_spawned() && e.spawned().entity_id() == bob.entity;
  };
  const int spawns_before = count_events(2, spawned);
  step(61);  // respawn delay 1 s
  ASSERT_TRUE(match().player_view(2)->alive);
  EXPECT_EQ(health(2), 100);
  EXPECT_EQ(count_events(2, spawned), spawns_before + 1);
  // At the spawn farthest from Alice, the only living enemy.
  const physics::Vec3 at = position(bob.entity);
  double farthest = 0;
  for (const MapSpawn& spawn : duel_map().spawns) {
    farthest = std::max(farthest, double((spawn.position_m - position(alice.entity)).norm()));
  }
  EXPECT_NEAR((at - position(alice.entity)).norm(), farthest, 0.5);
}

TEST_F(GameFixture, SpawnProtectionBlocksDamageForItsDuration) {
  MatchConfig config = quick_config();
  config.rules.spawn_protection_s = 1;
  start(config);
  Script& alice = join(1, "alice");
  Script& bob = join(2, "bob");
  step(5);
  aim(alice, bob.entity);
  alice.input.set_buttons(proto::kButtonFire);
  step(10);
  EXPECT_EQ(health(2), 100);  // protected
  step(60);
  EXPECT_LT(health(2), 100);
}

TEST_F(GameFixture, ArmourTakesItsShareUntilItRunsOut) {
  Vitals vitals{100, 10};
  const DamageResult first = apply_damage(vitals, 30, 0.66f);
  EXPECT_EQ(first.armor_lost + first.health_lost, 30);
  EXPECT_EQ(vitals.armor, 0);  // 20 of 30 would go to armour; only 10 was there
  EXPECT_EQ(vitals.health, 80);
}

TEST_F(GameFixture, FragLimitEndsTheMatchWithTheScoreboard) {
  MatchConfig config = quick_config();
  config.rules.frag_limit = 2;
  config.rules.respawn_delay_s = 0.1f;
  start(config);
  Script& alice = join(1, "alice");
  Script& bob = join(2, "bob");
  step(30);
  alice.input.set_buttons(proto::kButtonFire);
  for (int k = 0; k < 400 && !match().ended(); ++k) {
    if (match().player_view(2)->alive) aim(alice, bob.entity);
    step(1);
  }
  ASSERT_TRUE(match().ended());
  EXPECT_EQ(match().end_reason(), wire::MATCH_END_REASON_FRAG_LIMIT);
  EXPECT_EQ(score_of(1).kills, 2);
  EXPECT_EQ(score_of(2).deaths, 2);
  EXPECT_GT(score_of(1).ticks_played, 0u);
}

// --- teams ---

TEST_F(GameFixture, TeamsAreBalancedOnJoinAndFriendlyFireIsOffByDefault) {
  MatchConfig config = quick_config();
  config.rules.mode = GameMode::TeamDeathmatch;
  start(config);
  join(1, "a");
  join(2, "b");
  join(3, "c");
  join(4, "d");
  EXPECT_EQ(match().player_view(1)->team, Team::Red);
  EXPECT_EQ(match().player_view(2)->team, Team::Blue);
  EXPECT_EQ(match().player_view(3)->team, Team::Red);
  EXPECT_EQ(match().player_view(4)->team, Team::Blue);
  match().leave(2);
  scripts_.erase(2);
  join(5, "e");  // blue has one player fewer
  EXPECT_EQ(match().player_view(5)->team, Team::Blue);
  step(30);
  // Red shoots red: nothing.
  aim(scripts_[1], scripts_[3].entity);
  scripts_[1].input.set_buttons(proto::kButtonFire);
  step(20);
  EXPECT_EQ(health(3), 100);
}

// --- projectiles ---

TEST_F(GameFixture, RocketExplodesOnTheFloorNextToATargetAndLaunchesTheShooter) {
  start();
  Script& alice = join(1, "alice");
  Script& bob = join(2, "bob");
  step(30);
  // Aim at the floor 1.2 m in front of bob (on Alice's side).
  physics::Vec3 spot =
      position(bob.entity) + (position(alice.entity) - position(bob.entity)).normalized() * 1.2f;
  spot.y() = 0;
  aim_at(alice, spot);
  alice.input.set_weapon_slot(2);
  alice.input.set_buttons(proto::kButtonFire);
  step(1);
  alice.input.set_buttons(0);
  EXPECT_EQ(match().counters().shots_fired, 1u);
  step(40);
  EXPECT_EQ(match().counters().explosions, 1u);
  EXPECT_LT(health(2), 100);
  EXPECT_GT(health(2), 0);

  // A rocket at one's own feet: self damage at half and a jump.
  alice.input.set_pitch(-std::numbers::pi_v<float> / 2);
  step(60);
  alice.input.set_buttons(proto::kButtonFire);
  step(1);
  alice.input.set_buttons(0);
  float highest = 0;
  for (int k = 0; k < 40; ++k) {
    step(1);
    highest = std::max(highest, static_cast<float>(position(alice.entity).y()));
  }
  EXPECT_GT(highest, 1.0f);  // rocket jump
  EXPECT_LT(health(1), 100);
  EXPECT_GE(health(1), 40);  // self damage is halved
}

TEST_F(GameFixture, GrenadeBouncesAndExplodesOnItsFuseButNotThroughAWall) {
  Map map = duel_map();
  map.boxes.push_back(MapBox{physics::Vec3(0, 2, 0), physics::Vec3(10, 2, 0.2f), 0});
  start(quick_config(), map);
  Script& alice = join(1, "alice");
  Script& bob = join(2, "bob");
  step(30);
  aim(alice, bob.entity);  // straight into the wall
  alice.input.set_weapon_slot(3);
  alice.input.set_buttons(proto::kButtonFire);
  step(1);
  alice.input.set_buttons(0);
  const std::uint32_t fuse =
      static_cast<std::uint32_t>(std::lround(match().config().weapons.weapons[2].fuse_s * 60));
  step(static_cast<int>(fuse) + 2);
  EXPECT_EQ(match().counters().explosions, 1u);
  EXPECT_EQ(health(2), 100);  // behind the wall
}

TEST_F(GameFixture, ExplosionsNeverPushABodyFasterThanSnapshotsShow) {
  // Grenades lobbed straight up 0.6 s apart fall back along one line: each explodes on its fuse
  // about a metre from the next one, which a 500 N·s blast would send off at hundreds of m/s
  // (a grenade is 0.4 kg). Snapshots show at most max_speed_mps per axis: a blast may push a
  // body up to that speed, and only gravity (g·dt a tick) may take it past.
  start();
  Script& alice = join(1, "alice");
  step(10);
  alice.input.set_pitch(1.55f);
  alice.input.set_weapon_slot(3);
  alice.input.set_buttons(proto::kButtonFire);
  const float cap = match().config().quantization.max_speed_mps;
  const float gravity_per_tick = 9.81f / 60;
  std::map<std::uint32_t, float> speed_before;  // by grenade entity, at the previous tick
  float fastest = 0;
  for (int k = 0; k < 8 * 60; ++k) {
    step(1);
    std::map<std::uint32_t, float> speed;
    for (const proto::EntityState& state : match().entity_states()) {
      if (proto::entity_kind(state.flags) != proto::EntityKind::Grenade) continue;
      const auto& v = state.velocity_mps;
      speed[state.id] = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      fastest = std::max(fastest, speed[state.id]);
      const auto before = speed_before.find(state.id);
      const float allowed = std::max(cap, before == speed_before.end() ? 0.0f : before->second) +
                            gravity_per_tick + 0.01f;
      EXPECT_LE(speed[state.id], allowed) << "grenade " << state.id << " at tick " << k;
    }
    speed_before = std::move(speed);
  }
  EXPECT_GE(match().counters().explosions, 8u);
  EXPECT_GT(fastest, 0.9f * cap);  // the blasts did push grenades, up to the cap
}

// --- pickups and hazards ---

TEST_F(GameFixture, HealthPickupHealsAndComesBackOnItsTimer) {
  Map map = duel_map();
  // One 3 m to the +x side of each spawn: Alice is never hurt, so hers stays.
  for (const MapSpawn& spawn : duel_map().spawns) {
    map.pickups.push_back(
        MapPickup{PickupKind::Health, spawn.position_m + physics::Vec3(3, 0, 0), 25, 2.0f});
  }
  start(quick_config(), map);
  Script& alice = join(1, "alice");
  Script& bob = join(2, "bob");
  step(30);
  aim(alice, bob.entity);
  alice.input.set_buttons(proto::kButtonFire);
  step(12);  // two hits: shots at steps 1 and 7
  alice.input.set_buttons(0);
  ASSERT_EQ(health(2), 60);
  // Bob walks 3 m along +x onto the pickup by his spawn.
  bob.input.set_yaw(
      yaw_towards(position(bob.entity), position(bob.entity) + physics::Vec3(3, 0, 0)));
  bob.input.set_move_forward(127);
  for (int k = 0; k < 120 && health(2) == 60; ++k) step(1);
  EXPECT_EQ(health(2), 85);
  EXPECT_EQ(match().counters().pickups_taken, 1u);
  bob.input.set_move_forward(0);
  EXPECT_EQ(count_events(1,
                         [](const wire::GameEvent& e) {
                           return e.has_pickup() && e.pickup().entity_id() != 0;
                         }),
            1);
  step(125);
  EXPECT_EQ(count_events(1,
                         [](const wire::GameEvent& e) {
                           return e.has_pickup() && e.pickup().entity_id() == 0;
                         }),
            1);  // back after 2 s
}

TEST_F(GameFixture, KillVolumeKillsAndCostsAPoint) {
  Map map = duel_map();
  map.kill_volumes.push_back(
      MapKillVolume{"lava", physics::Vec3(-2, -1, 2), physics::Vec3(2, 1, 3)});
  start(quick_config(), map);
  Script& alice = join(1, "alice");
  step(5);
  // Alice's spawn is one of the two; walk towards z = 2.5 from wherever she is.
  const physics::Vec3 at = position(alice.entity);
  alice.input.set_yaw(yaw_towards(at, physics::Vec3(0, at.y(), 2.5f)));
  alice.input.set_move_forward(127);
  for (int k = 0; k < 240 && match().player_view(1)->alive; ++k) step(1);
  EXPECT_FALSE(match().player_view(1)->alive);
  EXPECT_EQ(score_of(1).score, -1);
  EXPECT_EQ(score_of(1).deaths, 1);
}

// --- input checks ---

TEST_F(GameFixture, AimSnapsFasterThanAPersonTurnsAreClampedAndCounted) {
  start();
  Script& alice = join(1, "alice");
  step(3);
  alice.input.set_yaw(3.0f);  // 3 rad in one tick: 180 rad/s
  step(1);
  EXPECT_EQ(match().player_view(1)->violations[static_cast<std::size_t>(Violation::TurnRate)], 1u);
  step(1);  // the aim catches up at 1 rad per tick
  step(1);
  EXPECT_EQ(match().player_view(1)->violations[static_cast<std::size_t>(Violation::TurnRate)], 2u);
  step(1);
  EXPECT_EQ(match().player_view(1)->violations[static_cast<std::size_t>(Violation::TurnRate)], 2u);
}

TEST_F(GameFixture, TriggerPressesFasterThanTheWeaponAreRefusedAndCounted) {
  start();
  Script& alice = join(1, "alice");
  step(3);
  for (int k = 0; k < 10; ++k) {  // press, release, press ... every tick: 30 presses/s
    alice.input.set_buttons(k % 2 == 0 ? std::uint32_t{proto::kButtonFire} : 0u);
    step(1);
  }
  // The rifle fires every 6 ticks: shots at k = 0 and k = 6; presses at 2, 4, 8 refused.
  EXPECT_EQ(score_of(1).shots, 2);
  EXPECT_EQ(match().player_view(1)->violations[static_cast<std::size_t>(Violation::FireRate)], 3u);
}

TEST_F(GameFixture, MoreInputsThanTicksAreRefusedAndCounted) {
  start();
  join(1, "alice");
  scripts_.clear();  // this test sends by hand
  std::uint32_t sequence = 0;
  for (int k = 0; k < 20; ++k) {  // 160 inputs within one tick
    wire::ClientPayload payload;
    for (int n = 0; n < 8; ++n) payload.add_inputs()->set_sequence(++sequence);
    std::vector<std::uint8_t> bytes(payload.ByteSizeLong());
    payload.SerializeToArray(bytes.data(), static_cast<int>(bytes.size()));
    match().receive(1, bytes);
  }
  EXPECT_GT(match().player_view(1)->violations[static_cast<std::size_t>(Violation::InputRate)], 0u);
}

// --- lag compensation in the match ---

/// Bob strafes across Alice's view; Alice fires at where Bob was `lag` ticks ago and says so.
class LagCompensatedShot : public GameFixture {
 protected:
  bool shoot_at_old_position(bool compensated) {
    MatchConfig config = quick_config();
    config.lag.enabled = compensated;
    start(config);
    Script& alice = join(1, "alice");
    Script& bob = join(2, "bob");
    step(30);
    aim(alice, bob.entity);  // face him first
    bob.input.set_move_right(127);
    step(30);                               // at full speed, 7 m/s
    constexpr std::uint32_t kLagTicks = 6;  // 100 ms
    const std::uint32_t seen_tick = match().tick_number() - kLagTicks;
    physics::Vec3 seen = physics::Vec3::Zero();
    for (const proto::EntityState& state : match().states_at(seen_tick)) {
      if (state.id == bob.entity)
        seen = {state.position_m[0], state.position_m[1], state.position_m[2]};
    }
    const physics::Vec3 eye = eye_position(position(alice.entity));
    alice.input.set_yaw(yaw_towards(eye, seen));  // a small turn from facing him
    alice.input.set_pitch(pitch_towards(eye, seen));
    alice.input.set_buttons(proto::kButtonFire);
    // The input is applied at the next step, when "now" is one tick later: claim the tick seen.
    alice.input.set_view_tick(seen_tick);
    match().set_latency(1, 50'000);  // 50 ms one way: the claim is within the trusted window
    step(1);
    return health(2) < 100;
  }
};

TEST_F(LagCompensatedShot, HitsWhereTheShooterSawTheTarget) {
  EXPECT_TRUE(shoot_at_old_position(true));
}

TEST_F(LagCompensatedShot, MissesWithoutCompensation) {
  EXPECT_FALSE(shoot_at_old_position(false));
}

TEST_F(GameFixture, ViewTickClaimsOutsideTheWindowAreClampedAndCounted) {
  start();
  Script& alice = join(1, "alice");
  join(2, "bob");
  step(120);
  alice.input.set_buttons(proto::kButtonFire);
  alice.input.set_view_tick(match().tick_number() - 100);  // 1.7 s back
  step(1);
  EXPECT_EQ(match().counters().view_claims_clamped, 1u);
  EXPECT_EQ(match().player_view(1)->violations[static_cast<std::size_t>(Violation::ViewTick)], 1u);
}

// --- determinism ---

TEST_F(GameFixture, TheSameScriptGivesTheSameHash) {
  std::vector<std::uint64_t> hashes;
  for (int run = 0; run < 2; ++run) {
    scripts_.clear();
    now_ = kStart;
    MatchConfig config = quick_config();
    config.weapons.weapons[0].spread_rad = 0.02f;
    start(config);
    Script& alice = join(1, "alice");
    Script& bob = join(2, "bob");
    step(20);
    alice.input.set_buttons(proto::kButtonFire);
    bob.input.set_move_right(90);
    bob.input.set_weapon_slot(3);
    bob.input.set_buttons(proto::kButtonFire);
    for (int k = 0; k < 300; ++k) {
      aim(alice, bob.entity);
      alice.input.set_weapon_slot(k % 100 < 50 ? 1 : 2);
      step(1);
    }
    hashes.push_back(match().state_hash());
  }
  EXPECT_EQ(hashes[0], hashes[1]);
}

}  // namespace
}  // namespace ricochet::server::match_game_test
