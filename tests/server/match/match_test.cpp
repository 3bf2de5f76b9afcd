// A match driven by fake time: players, untrusted payloads, the tick, snapshots, events, chat,
// reconnects.

#include "ricochet/server/match.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <map>

#include "ricochet/proto/entity_flags.h"

namespace ricochet::server::match_test {
namespace {

using proto::kMicrosPerSecond;
using proto::TimeUs;

constexpr TimeUs kStart = 1'000'000;
constexpr TimeUs kTickUs = kMicrosPerSecond / 60 + 1;  // a little over one 60 Hz period

Map sample_map() {
  const std::string path = std::string(RICOCHET_SOURCE_DIR "/server/maps/arena.toml");
  MapResult result = load_map_file(path);
  EXPECT_TRUE(std::holds_alternative<Map>(result));
  return std::get<Map>(std::move(result));
}

/// What one account received, decoded.
struct Inbox {
  std::vector<wire::GameEvent> events;
  std::vector<wire::GameEvent> game_events;
  std::vector<wire::ServerPayload> payloads;
};

class MatchFixture : public ::testing::Test {
 protected:
  explicit MatchFixture(MatchConfig config = {}) : match_(make(config)) {}

  static Match make(const MatchConfig& config) {
    auto created = Match::create(config, sample_map(), kStart);
    if (auto* error = std::get_if<std::string>(&created)) ADD_FAILURE() << *error;
    return std::get<Match>(std::move(created));
  }

  /// Runs the match to `now_` + `us`, draining the outbox into the inboxes.
  int advance(TimeUs us) {
    int steps = 0;
    const TimeUs until = now_ + us;
    while (now_ < until) {
      now_ = std::min(until, now_ + kMicrosPerSecond / 120);
      steps += match_.tick(now_);
      drain();
    }
    return steps;
  }
  void drain() {
    Outgoing out;
    std::size_t left = match_.outbox_size();
    while (match_.poll_outbox(out)) {
      ASSERT_GT(left, 0u) << "outbox_size counts every message poll_outbox gives";
      --left;
      Inbox& inbox = inboxes_[out.account];
      if (out.reliable) {
        wire::GameEvent event;
        ASSERT_TRUE(event.ParseFromArray(out.bytes.data(), static_cast<int>(out.bytes.size())));
        // The game's own events (match_game_test.cpp tests them) are kept apart, so that these
        // tests see the membership, chat and end events alone.
        const bool game = event.has_match_state() || event.has_spawned() || event.has_hit() ||
                          event.has_kill() || event.has_pickup();
        (game ? inbox.game_events : inbox.events).push_back(std::move(event));
      } else {
        EXPECT_LE(out.bytes.size(), match_.config().snapshot_budget_bytes);
        ASSERT_TRUE(inbox.payloads.emplace_back().ParseFromArray(
            out.bytes.data(), static_cast<int>(out.bytes.size())));
      }
    }
    EXPECT_EQ(left, 0u);
    EXPECT_EQ(match_.outbox_size(), 0u);
  }

  std::uint32_t join(std::uint64_t account, const std::string& name) {
    auto joined = match_.connect(account, name);
    EXPECT_TRUE(std::holds_alternative<Joined>(joined));
    return std::holds_alternative<Joined>(joined) ? std::get<Joined>(joined).entity_id : 0;
  }

  static std::vector<std::uint8_t> bytes(const wire::ClientPayload& payload) {
    std::vector<std::uint8_t> out(payload.ByteSizeLong());
    payload.SerializeToArray(out.data(), static_cast<int>(out.size()));
    return out;
  }

  /// A payload carrying inputs first..last (redundancy), each moving with `forward` and `buttons`.
  static wire::ClientPayload inputs(std::uint32_t first, std::uint32_t last, int forward,
                                    std::uint32_t buttons = 0, float yaw = 0) {
    wire::ClientPayload payload;
    for (std::uint32_t s = first; s <= last; ++s) {
      wire::Input& in = *payload.add_inputs();
      in.set_sequence(s);
      in.set_move_forward(forward);
      in.set_buttons(buttons);
      in.set_yaw(yaw);
    }
    return payload;
  }

  const proto::EntityState& state_of(std::uint32_t entity) const {
    for (const proto::EntityState& state : match_.entity_states()) {
      if (state.id == entity) return state;
    }
    static const proto::EntityState none{};
    ADD_FAILURE() << "no entity " << entity;
    return none;
  }

  std::uint64_t drops(InputDrop reason) const {
    return match_.counters().input_drops[static_cast<std::size_t>(reason)];
  }

  Match match_;
  TimeUs now_ = kStart;
  std::map<std::uint64_t, Inbox> inboxes_;
};

TEST(MatchConfig, ValidatesEveryRange) {
  EXPECT_EQ(MatchConfig{}.validate(), "");
  MatchConfig config;
  config.max_players = 65;
  EXPECT_EQ(config.validate(), "match max_players must be 1..64, got 65");
  config = {};
  config.tick.rate_hz = 200;
  EXPECT_EQ(config.validate(), "match tick rate_hz must be 10..128, got 200");
  config = {};
  config.snapshot_rate_hz = 61;
  EXPECT_EQ(config.validate(), "match snapshot_rate_hz must be 1..tick rate_hz (60), got 61");
  config = {};
  config.snapshot_budget_bytes = 1200;
  EXPECT_EQ(config.validate(), "match snapshot_budget_bytes must be 192..1100, got 1200");
  config = {};
  config.name = "";
  EXPECT_NE(config.validate().find("match name"), std::string::npos);
  config = {};
  config.movement.jump_speed_mps = -1;
  EXPECT_NE(config.validate().find("match movement jump_speed_mps"), std::string::npos);
  auto refused = Match::create(config, sample_map(), 0);
  ASSERT_TRUE(std::holds_alternative<std::string>(refused));
}

TEST_F(MatchFixture, TicksAtTheFixedRateFromTheCallersTime) {
  EXPECT_EQ(match_.tick(kStart), 0);
  EXPECT_EQ(advance(kMicrosPerSecond), 60);
  EXPECT_EQ(match_.tick_number(), 60u);
  EXPECT_EQ(match_.counters().steps, 60u);
  EXPECT_EQ(match_.counters().overruns, 0u);
  EXPECT_GT(match_.next_tick_at(), now_);
  EXPECT_LE(match_.next_tick_at(), now_ + kTickUs);
}

TEST_F(MatchFixture, AStallRunsAtMostTheCatchUpCap) {
  EXPECT_EQ(match_.tick(kStart + kMicrosPerSecond), 5);  // 60 due, cap 5
  EXPECT_EQ(match_.profile().steps, 5);
  EXPECT_EQ(match_.counters().overruns, 1u);
  EXPECT_EQ(match_.counters().dropped_steps, 55u);
}

TEST_F(MatchFixture, JoinsAnnounceEveryoneToEveryone) {
  const std::uint32_t ann = join(11, "ann");
  const std::uint32_t bob = join(22, "bob");
  EXPECT_NE(ann, bob);
  EXPECT_EQ(match_.player_count(), 2);
  advance(kTickUs);
  const auto joined_ids = [&](std::uint64_t account) {
    std::vector<std::uint32_t> ids;
    for (const wire::GameEvent& event : inboxes_[account].events) {
      EXPECT_TRUE(event.has_player_joined());
      EXPECT_FALSE(event.player_joined().reconnected());
      ids.push_back(event.player_joined().entity_id());
    }
    return ids;
  };
  EXPECT_EQ(joined_ids(11), (std::vector<std::uint32_t>{ann, bob}));
  EXPECT_EQ(joined_ids(22), (std::vector<std::uint32_t>{ann, bob}));
  EXPECT_EQ(inboxes_[22].events[0].player_joined().name(), "ann");
  EXPECT_EQ(match_.counters().players_joined, 2u);
  // The two spawn apart.
  const auto& a = state_of(ann).position_m;
  const auto& b = state_of(bob).position_m;
  EXPECT_GT(std::hypot(a[0] - b[0], a[2] - b[2]), 1.0);
}

TEST_F(MatchFixture, EveryConnectedPlayerGetsADecodableSnapshotPerTick) {
  const std::uint32_t ann = join(11, "ann");
  join(22, "bob");
  advance(kMicrosPerSecond / 2);
  proto::SnapshotDecoder decoder(match_.config().quantization);
  const std::vector<wire::ServerPayload>& payloads = inboxes_[11].payloads;
  ASSERT_EQ(payloads.size(), 30u);
  std::vector<proto::QuantizedEntity> view;
  for (const wire::ServerPayload& payload : payloads) {
    EXPECT_EQ(payload.your_entity_id(), ann);
    EXPECT_EQ(payload.snapshot().tick(), payload.server_tick());
    const proto::SnapshotDecodeResult decoded = decoder.decode(payload.snapshot());
    ASSERT_TRUE(decoded.ok) << decoded.message;
    view.assign(decoded.entities.begin(), decoded.entities.end());
  }
  // The last one is the match's state now, quantised, bit for bit.
  EXPECT_EQ(payloads.back().server_tick(), match_.tick_number());
  const std::span<const proto::EntityState> states = match_.entity_states();
  ASSERT_EQ(view.size(), 2u);
  ASSERT_EQ(states.size(), 2u);
  for (std::size_t k = 0; k < states.size(); ++k) {
    EXPECT_EQ(view[k], proto::quantize(states[k], match_.config().quantization));
  }
  EXPECT_EQ(inboxes_[22].payloads.size(), 30u);
  EXPECT_EQ(match_.counters().snapshots_sent, 60u);
}

TEST_F(MatchFixture, AcknowledgedSnapshotsShrinkToDeltas) {
  join(11, "ann");
  advance(kMicrosPerSecond / 2);  // settle on the floor
  proto::SnapshotDecoder decoder(match_.config().quantization);
  std::size_t last_size = 0;
  for (int k = 0; k < 10; ++k) {
    inboxes_[11].payloads.clear();
    advance(kTickUs);
    ASSERT_FALSE(inboxes_[11].payloads.empty());
    const wire::ServerPayload& payload = inboxes_[11].payloads.back();
    ASSERT_TRUE(decoder.decode(payload.snapshot()).ok);
    wire::ClientPayload ack;
    ack.set_ack_snapshot_tick(decoder.newest_tick());
    match_.receive(11, bytes(ack));
    last_size = payload.snapshot().ByteSizeLong();
  }
  EXPECT_GT(inboxes_[11].payloads.back().snapshot().baseline_age(), 0u);
  EXPECT_LT(last_size, 16u);  // a resting entity against its baseline
}

// Acks reach the encoder when the next snapshot is built; between two snapshots the newest one
// counts, whatever order the packets came in.
TEST_F(MatchFixture, TheNewestAckBetweenTwoSnapshotsIsTheBaseline) {
  join(11, "ann");
  advance(kMicrosPerSecond / 4);
  proto::SnapshotDecoder decoder(match_.config().quantization);
  std::vector<std::uint32_t> ticks;
  for (int k = 0; k < 3; ++k) {
    inboxes_[11].payloads.clear();
    advance(kTickUs);
    ASSERT_EQ(inboxes_[11].payloads.size(), 1u);
    ASSERT_TRUE(decoder.decode(inboxes_[11].payloads.back().snapshot()).ok);
    ticks.push_back(decoder.newest_tick());
  }
  for (const std::uint32_t tick : {ticks[2], ticks[0], ticks[1]}) {  // reordered
    wire::ClientPayload ack;
    ack.set_ack_snapshot_tick(tick);
    match_.receive(11, bytes(ack));
  }
  inboxes_[11].payloads.clear();
  advance(kTickUs);
  ASSERT_EQ(inboxes_[11].payloads.size(), 1u);
  const wire::ServerPayload& next = inboxes_[11].payloads.back();
  EXPECT_EQ(next.server_tick() - next.snapshot().baseline_age(), ticks[2]);
  EXPECT_TRUE(decoder.decode(next.snapshot()).ok);
}

TEST_F(MatchFixture, InputsMoveThePlayerAndTheAppliedSequenceIsEchoed) {
  const std::uint32_t ann = join(11, "ann");
  advance(kMicrosPerSecond / 4);
  const auto start = state_of(ann).position_m;
  // 30 ticks of forward input (yaw 0: along -Z), each packet repeating the last three.
  for (std::uint32_t s = 1; s <= 30; ++s) {
    match_.receive(11, bytes(inputs(s > 2 ? s - 2 : 1, s, 127)));
    advance(kTickUs);
  }
  const auto end = state_of(ann).position_m;
  EXPECT_LT(end[2] - start[2], -1.5);  // accelerating to 7 m/s over half a second
  EXPECT_NEAR(end[0], start[0], 1e-3);
  EXPECT_EQ(inboxes_[11].payloads.back().last_input_sequence(), 30u);
  EXPECT_GE(match_.counters().inputs_applied, 29u);
  EXPECT_GT(drops(InputDrop::Stale), 0u);  // the redundancy
  // No more input: the last one repeats, the echo stays.
  advance(kTickUs * 3);
  EXPECT_EQ(inboxes_[11].payloads.back().last_input_sequence(), 30u);
  EXPECT_GE(match_.counters().inputs_repeated, 3u);
}

TEST_F(MatchFixture, AJumpLeavesTheFloorOnce) {
  const std::uint32_t ann = join(11, "ann");
  advance(kMicrosPerSecond / 2);
  const float ground_y = state_of(ann).position_m[1];
  EXPECT_TRUE(state_of(ann).flags & proto::kEntityGrounded);
  float peak = ground_y;
  for (std::uint32_t s = 1; s <= 30; ++s) {  // holding jump for half a second
    match_.receive(11, bytes(inputs(s, s, 0, proto::kButtonJump)));
    advance(kTickUs);
    peak = std::max(peak, state_of(ann).position_m[1]);
  }
  EXPECT_NEAR(peak - ground_y, 1.23, 0.05);
  EXPECT_FALSE(state_of(ann).flags & proto::kEntityGrounded);
}

TEST_F(MatchFixture, BadPayloadsAreDroppedAndCountedByReason) {
  const std::uint32_t ann = join(11, "ann");
  advance(kTickUs);
  const auto before = state_of(ann).position_m;
  const std::uint8_t garbage[] = {0xFF, 0xFF, 0xFF, 0xFF, 0x0F};
  match_.receive(11, garbage);
  match_.receive(11, std::vector<std::uint8_t>(1201, 0));
  match_.receive(11, bytes(inputs(1, 9, 127)));  // 9 inputs
  wire::ClientPayload nan = inputs(1, 1, 127);
  nan.mutable_inputs(0)->set_yaw(std::numeric_limits<float>::quiet_NaN());
  match_.receive(11, bytes(nan));
  wire::ClientPayload inf = inputs(1, 1, 127);
  inf.mutable_inputs(0)->set_pitch(-std::numeric_limits<float>::infinity());
  match_.receive(11, bytes(inf));
  match_.receive(11, bytes(inputs(1, 1, 500)));
  match_.receive(11, bytes(inputs(1, 1, 127, 1u << 9)));
  match_.receive(11, bytes(inputs(0, 0, 127)));
  match_.receive(99, bytes(inputs(1, 1, 127)));  // not in the match
  EXPECT_EQ(drops(InputDrop::MalformedPayload), 2u);
  EXPECT_EQ(drops(InputDrop::TooManyInputs), 1u);
  EXPECT_EQ(drops(InputDrop::NonFinite), 2u);
  EXPECT_EQ(drops(InputDrop::OutOfRange), 2u);
  EXPECT_EQ(drops(InputDrop::ZeroSequence), 1u);
  EXPECT_EQ(drops(InputDrop::UnknownPlayer), 1u);
  EXPECT_EQ(match_.counters().payloads_received, 5u);
  // Nothing moved the player, nothing crashed, the match goes on.
  advance(kMicrosPerSecond / 4);
  const auto after = state_of(ann).position_m;
  EXPECT_NEAR(after[0], before[0], 1e-3);
  EXPECT_NEAR(after[2], before[2], 1e-3);
  EXPECT_EQ(inboxes_[11].payloads.back().last_input_sequence(), 0u);
  // An ack for a tick never sent is ignored.
  wire::ClientPayload ack;
  ack.set_ack_snapshot_tick(123456);
  match_.receive(11, bytes(ack));
  advance(kTickUs);
  EXPECT_EQ(inboxes_[11].payloads.back().snapshot().baseline_age(), 0u);
}

TEST_F(MatchFixture, AReconnectWithinTheGraceKeepsTheEntity) {
  const std::uint32_t ann = join(11, "ann");
  join(22, "bob");
  for (std::uint32_t s = 1; s <= 10; ++s) {
    match_.receive(11, bytes(inputs(s, s, 127)));
    advance(kTickUs);
  }
  match_.disconnect(11, now_);
  EXPECT_EQ(match_.connected_count(), 1);
  EXPECT_EQ(match_.player_count(), 2);
  inboxes_.clear();
  advance(kMicrosPerSecond);
  EXPECT_TRUE(inboxes_[11].payloads.empty());  // nothing for the one away
  EXPECT_TRUE(state_of(ann).flags & proto::kEntityDisconnected);
  EXPECT_EQ(match_.chat(11, "hello?"), ChatDrop::NotInMatch);
  match_.receive(11, bytes(inputs(11, 11, 127)));
  EXPECT_EQ(drops(InputDrop::UnknownPlayer), 1u);
  const auto standing = state_of(ann).position_m;
  advance(kMicrosPerSecond);
  EXPECT_NEAR(state_of(ann).position_m[2], standing[2], 1e-3);  // stands still while away

  auto back = match_.connect(11, "ann");
  ASSERT_TRUE(std::holds_alternative<Joined>(back));
  EXPECT_EQ(std::get<Joined>(back).entity_id, ann);
  EXPECT_TRUE(std::get<Joined>(back).reconnected);
  advance(kTickUs);
  EXPECT_FALSE(state_of(ann).flags & proto::kEntityDisconnected);
  ASSERT_FALSE(inboxes_[22].events.empty());
  EXPECT_TRUE(inboxes_[22].events.back().player_joined().reconnected());
  // The one back hears of bob, then of itself.
  ASSERT_EQ(inboxes_[11].events.size(), 2u);
  EXPECT_EQ(inboxes_[11].events[0].player_joined().name(), "bob");
  EXPECT_FALSE(inboxes_[11].events[0].player_joined().reconnected());
  EXPECT_EQ(inboxes_[11].events[1].player_joined().entity_id(), ann);
  EXPECT_TRUE(inboxes_[11].events[1].player_joined().reconnected());
  // The new client starts its sequence at 1 again and gets a full snapshot.
  ASSERT_FALSE(inboxes_[11].payloads.empty());
  EXPECT_EQ(inboxes_[11].payloads.front().snapshot().baseline_age(), 0u);
  EXPECT_EQ(inboxes_[11].payloads.front().last_input_sequence(), 0u);
  match_.receive(11, bytes(inputs(1, 1, 127)));
  advance(kTickUs);
  EXPECT_EQ(inboxes_[11].payloads.back().last_input_sequence(), 1u);
  EXPECT_EQ(match_.counters().players_reconnected, 1u);
}

/// At 10 Hz, for tests that run through long stretches of match time.
class TenHertzMatch : public MatchFixture {
 protected:
  TenHertzMatch() : MatchFixture(config()) {}
  static MatchConfig config() {
    MatchConfig config;
    config.tick.rate_hz = 10;
    config.snapshot_rate_hz = 10;
    return config;
  }
};

TEST_F(TenHertzMatch, APlayerAwayLongerThanTheGraceIsRemoved) {
  const std::uint32_t ann = join(11, "ann");
  join(22, "bob");
  advance(kTickUs);
  match_.disconnect(11, now_);
  inboxes_.clear();
  advance(29 * kMicrosPerSecond);
  EXPECT_EQ(match_.player_count(), 2);
  advance(kMicrosPerSecond + kMicrosPerSecond / 5);
  EXPECT_EQ(match_.player_count(), 1);
  EXPECT_FALSE(match_.entity_of(11));
  EXPECT_EQ(match_.entity_states().size(), 1u);
  ASSERT_EQ(inboxes_[22].events.size(), 1u);
  const wire::PlayerLeft& left = inboxes_[22].events[0].player_left();
  EXPECT_EQ(left.entity_id(), ann);
  EXPECT_EQ(left.reason(), wire::LEAVE_REASON_TIMED_OUT);
  EXPECT_EQ(match_.counters().players_timed_out, 1u);
  // Coming back later is a new entity.
  auto again = match_.connect(11, "ann");
  ASSERT_TRUE(std::holds_alternative<Joined>(again));
  EXPECT_NE(std::get<Joined>(again).entity_id, ann);
  EXPECT_FALSE(std::get<Joined>(again).reconnected);
}

TEST_F(MatchFixture, LeavingIsAtOnce) {
  join(11, "ann");
  const std::uint32_t bob = join(22, "bob");
  advance(kTickUs);
  inboxes_.clear();
  EXPECT_TRUE(match_.leave(22));
  EXPECT_FALSE(match_.leave(22));
  advance(kTickUs);
  ASSERT_EQ(inboxes_[11].events.size(), 1u);
  EXPECT_EQ(inboxes_[11].events[0].player_left().entity_id(), bob);
  EXPECT_EQ(inboxes_[11].events[0].player_left().reason(), wire::LEAVE_REASON_LEFT);
  EXPECT_TRUE(inboxes_[22].payloads.empty());
  EXPECT_EQ(match_.counters().players_left, 1u);
}

TEST_F(MatchFixture, ChatIsEchoedToEveryoneAndBadLinesAreRefused) {
  const std::uint32_t ann = join(11, "ann");
  join(22, "bob");
  advance(kTickUs);
  inboxes_.clear();
  EXPECT_EQ(match_.chat(11, "gl hf \xC3\xA9"), std::nullopt);
  EXPECT_EQ(match_.chat(99, "hi"), ChatDrop::NotInMatch);
  EXPECT_EQ(match_.chat(11, ""), ChatDrop::Empty);
  EXPECT_EQ(match_.chat(11, std::string(201, 'a')), ChatDrop::TooLong);
  EXPECT_EQ(match_.chat(11, std::string(200, 'a')), std::nullopt);
  EXPECT_EQ(match_.chat(11, "bell\a"), ChatDrop::InvalidText);
  EXPECT_EQ(match_.chat(11, "\xC0\xAF"), ChatDrop::InvalidText);      // overlong '/'
  EXPECT_EQ(match_.chat(11, "\xED\xA0\x80"), ChatDrop::InvalidText);  // a surrogate
  EXPECT_EQ(match_.chat(11, "cut \xE2\x82"), ChatDrop::InvalidText);
  EXPECT_EQ(match_.chat(11,
                        "\xE2\x80\xAE"
                        "olleh"),
            ChatDrop::InvalidText);  // U+202E
  advance(kTickUs);
  for (const std::uint64_t account : {11u, 22u}) {
    ASSERT_EQ(inboxes_[account].events.size(), 2u);
    const wire::ChatMessage& line = inboxes_[account].events[0].chat();
    EXPECT_EQ(line.entity_id(), ann);
    EXPECT_EQ(line.name(), "ann");
    EXPECT_EQ(line.text(), "gl hf \xC3\xA9");
  }
  const auto& drops = match_.counters().chat_drops;
  EXPECT_EQ(drops[static_cast<std::size_t>(ChatDrop::NotInMatch)], 1u);
  EXPECT_EQ(drops[static_cast<std::size_t>(ChatDrop::InvalidText)], 5u);
  EXPECT_EQ(match_.counters().chat_messages, 2u);
}

TEST_F(MatchFixture, RefusesPlayersBeyondTheCapAndBadNames) {
  for (std::uint64_t account = 1; account <= 16; ++account) {
    std::string name = "p";
    name += std::to_string(account);
    join(account, name);
  }
  EXPECT_EQ(match_.connect(17, "late"),
            (std::variant<Joined, JoinRefusal>(JoinRefusal::MatchFull)));
  EXPECT_EQ(match_.connect(18, ""), (std::variant<Joined, JoinRefusal>(JoinRefusal::InvalidName)));
  EXPECT_EQ(match_.connect(18, "new\nline"),
            (std::variant<Joined, JoinRefusal>(JoinRefusal::InvalidName)));
  // A seated player reconnecting (a new connection replacing its open one) is not refused for
  // the cap, and hears of the 15 others and itself once, not also what was queued before.
  EXPECT_TRUE(std::holds_alternative<Joined>(match_.connect(16, "p16")));
  drain();
  EXPECT_EQ(inboxes_[16].events.size(), 0u);  // events go out with the next tick
  advance(kTickUs);
  EXPECT_EQ(inboxes_[16].events.size(), 16u);
  EXPECT_TRUE(inboxes_[16].events.back().player_joined().reconnected());
  EXPECT_EQ(match_.counters().join_refusals[static_cast<std::size_t>(JoinRefusal::MatchFull)], 1u);
  // Sixteen players on sixteen spawns, a snapshot each within the budget.
  advance(kMicrosPerSecond / 2);
  EXPECT_EQ(match_.entity_states().size(), 16u);
  EXPECT_EQ(inboxes_[1].payloads.size(), 31u);  // one tick, then half a second
}

TEST(MatchCrowd, SixtyFourPlayersOnSixteenSpawnsRunAroundWithinBounds) {
  MatchConfig config;
  config.max_players = 64;
  config.snapshot_rate_hz = 10;  // 64 encoders of 64 entities: keep it quick under sanitizers
  auto created = Match::create(config, sample_map(), kStart);
  ASSERT_TRUE(std::holds_alternative<Match>(created));
  Match& match = std::get<Match>(created);
  for (std::uint64_t account = 1; account <= 64; ++account) {
    ASSERT_TRUE(std::holds_alternative<Joined>(match.connect(account, "crowd")));
  }
  // Spawned apart: 16 on the floor, the others one player height above each other.
  std::vector<std::uint8_t> payload_bytes;
  std::uint32_t sequence = 0;
  std::size_t largest_payload = 0;
  TimeUs now = kStart;
  for (int tick = 0; tick < 90; ++tick) {  // 1.5 s
    ++sequence;
    for (std::uint64_t account = 1; account <= 64; ++account) {
      wire::ClientPayload payload;
      wire::Input& in = *payload.add_inputs();
      in.set_sequence(sequence);
      in.set_move_forward(127);
      in.set_yaw(std::remainder(static_cast<float>(account) * 0.7f + static_cast<float>(tick / 40),
                                6.2831853f));
      in.set_buttons(tick % 50 == static_cast<int>(account % 50) ? std::uint32_t{proto::kButtonJump}
                                                                 : 0u);
      payload_bytes.resize(payload.ByteSizeLong());
      payload.SerializeToArray(payload_bytes.data(), static_cast<int>(payload_bytes.size()));
      match.receive(account, payload_bytes);
    }
    now += kTickUs;
    match.tick(now);
    Outgoing out;
    while (match.poll_outbox(out)) {
      if (!out.reliable) largest_payload = std::max(largest_payload, out.bytes.size());
    }
  }
  EXPECT_LE(largest_payload, config.snapshot_budget_bytes);
  const Map map = sample_map();
  ASSERT_EQ(match.entity_states().size(), 64u);
  for (const proto::EntityState& state : match.entity_states()) {
    const physics::Vec3 position(state.position_m[0], state.position_m[1], state.position_m[2]);
    EXPECT_TRUE(position.allFinite());
    EXPECT_TRUE(map.contains(position)) << state.id << ": " << position.transpose();
    EXPECT_LT(position.y(), 3.0) << state.id;  // everyone came down; nobody was launched
  }
  EXPECT_EQ(match.counters().inputs_applied, 64u * 90u);
  EXPECT_EQ(match.counters().snapshots_sent, 64u * 15u);
}

/// The same joins, payloads and times give the same world, bit for bit: replays are exact.
TEST(MatchReplay, TheSameInputsAndTimesGiveTheSameStates) {
  const auto run = [] {
    auto created = Match::create(MatchConfig{}, sample_map(), kStart);
    Match match = std::get<Match>(std::move(created));
    for (std::uint64_t account = 1; account <= 4; ++account) {
      EXPECT_TRUE(std::holds_alternative<Joined>(match.connect(account, "p")));
    }
    TimeUs now = kStart;
    for (std::uint32_t sequence = 1; sequence <= 120; ++sequence) {
      for (std::uint64_t account = 1; account <= 4; ++account) {
        wire::ClientPayload payload;
        wire::Input& in = *payload.add_inputs();
        in.set_sequence(sequence);
        in.set_move_forward(static_cast<int>(sequence * account % 255) - 127);
        in.set_move_right(static_cast<int>(account * 40) - 100);
        in.set_yaw(std::remainder(0.05f * static_cast<float>(sequence * account), 6.2831853f));
        in.set_buttons(sequence % 37 == account ? std::uint32_t{proto::kButtonJump} : 0u);
        std::vector<std::uint8_t> bytes(payload.ByteSizeLong());
        payload.SerializeToArray(bytes.data(), static_cast<int>(bytes.size()));
        match.receive(account, bytes);
      }
      now += kTickUs + static_cast<TimeUs>(sequence % 7) * 1000;  // uneven polling
      match.tick(now);
      Outgoing out;
      while (match.poll_outbox(out)) {
      }
    }
    return std::make_pair(match.world().state_hash(),
                          std::vector<proto::EntityState>(match.entity_states().begin(),
                                                          match.entity_states().end()));
  };
  const auto first = run();
  const auto second = run();
  EXPECT_EQ(first.first, second.first);
  ASSERT_EQ(first.second.size(), 4u);
  for (std::size_t k = 0; k < first.second.size(); ++k) {
    EXPECT_EQ(first.second[k].position_m, second.second[k].position_m);
    EXPECT_EQ(first.second[k].velocity_mps, second.second[k].velocity_mps);
    EXPECT_EQ(first.second[k].flags, second.second[k].flags);
  }
}

TEST_F(MatchFixture, EndingTellsEveryConnectedPlayerAtOnce) {
  join(11, "ann");
  join(22, "bob");
  join(33, "cid");
  advance(kTickUs);
  match_.disconnect(33, now_);
  inboxes_.clear();
  EXPECT_EQ(match_.chat(11, "bye"), std::nullopt);
  match_.end(wire::MATCH_END_REASON_SERVER_SHUTDOWN);
  EXPECT_TRUE(match_.ended());
  drain();  // no tick needed
  for (const std::uint64_t account : {11u, 22u}) {
    const Inbox& inbox = inboxes_[account];
    ASSERT_EQ(inbox.events.size(), 2u);
    EXPECT_EQ(inbox.events[0].chat().text(), "bye");
    EXPECT_EQ(inbox.events[1].match_ended().reason(), wire::MATCH_END_REASON_SERVER_SHUTDOWN);
    EXPECT_TRUE(inbox.payloads.empty());
  }
  EXPECT_TRUE(inboxes_[33].events.empty());
  EXPECT_EQ(match_.connect(44, "dan"),
            (std::variant<Joined, JoinRefusal>(JoinRefusal::MatchEnded)));
}

TEST_F(MatchFixture, TheHistoryKeepsTheLastTicks) {
  join(11, "ann");
  advance(2 * kMicrosPerSecond);
  const std::uint32_t now_tick = match_.tick_number();
  EXPECT_EQ(match_.states_at(now_tick).size(), 1u);
  EXPECT_EQ(match_.states_at(now_tick - 63).size(), 1u);
  EXPECT_TRUE(match_.states_at(now_tick - 64).empty());
  EXPECT_TRUE(match_.states_at(now_tick + 1).empty());
}

TEST(MatchProfile, FillsEveryPhaseFromTheProfileClock) {
  std::int64_t fake_ns = 0;
  auto created = Match::create(MatchConfig{}, sample_map(), kStart, [&fake_ns] {
    fake_ns += 1000;  // every read is 1 µs later
    return fake_ns;
  });
  ASSERT_TRUE(std::holds_alternative<Match>(created));
  Match& match = std::get<Match>(created);
  ASSERT_TRUE(std::holds_alternative<Joined>(match.connect(1, "ann")));
  EXPECT_EQ(match.tick(kStart + 2 * kTickUs), 2);
  const TickProfile& profile = match.profile();
  EXPECT_EQ(profile.steps, 2);
  EXPECT_TRUE(profile.snapshot);
  for (const double ms : {profile.apply_inputs_ms, profile.movement_ms, profile.physics_ms,
                          profile.history_ms, profile.snapshots_ms, profile.send_ms}) {
    EXPECT_GT(ms, 0);
  }
  EXPECT_GE(profile.total_ms, profile.apply_inputs_ms + profile.movement_ms + profile.physics_ms +
                                  profile.history_ms + profile.snapshots_ms + profile.send_ms);
  EXPECT_EQ(match.tick(kStart + 2 * kTickUs), 0);
  EXPECT_EQ(match.profile().steps, 0);
  EXPECT_FALSE(match.profile().snapshot);
}

TEST(MatchSnapshotRate, SendsAtTheSnapshotRate) {
  MatchConfig config;
  config.snapshot_rate_hz = 20;
  auto created = Match::create(config, sample_map(), kStart);
  ASSERT_TRUE(std::holds_alternative<Match>(created));
  Match& match = std::get<Match>(created);
  ASSERT_TRUE(std::holds_alternative<Joined>(match.connect(1, "ann")));
  int payloads = 0;
  for (TimeUs t = kStart; t <= kStart + kMicrosPerSecond; t += 1000) {
    match.tick(t);
    Outgoing out;
    while (match.poll_outbox(out)) payloads += out.reliable ? 0 : 1;
  }
  EXPECT_EQ(payloads, 20);
}

}  // namespace
}  // namespace ricochet::server::match_test
