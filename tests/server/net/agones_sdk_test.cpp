// AgonesSdk, the sans-IO state machine of the Agones SDK calls, on fake time: which call goes
// when, with what path and body (the contract of Agones' sdk.swagger.json), and what a sidecar
// that is late or fails does to it.
//
//   POST /ready {}, POST /health {}, POST /allocate {}, POST /shutdown {},
//   PUT /metadata/label {"key":"<key>","value":"<value>"}, GET /gameserver
#include "agones_sdk.h"

#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

namespace ricochet::server::agones_sdk_test {
namespace {

constexpr proto::TimeUs kMs = proto::kMicrosPerMilli;
constexpr proto::TimeUs kSecond = proto::kMicrosPerSecond;

/// One match on the arena, ticking at `last_tick_at`.
AgonesMatchView match_view(proto::TimeUs last_tick_at, int players = 0,
                           std::uint64_t overruns = 0) {
  return AgonesMatchView{.id = 1,
                         .map = "arena",
                         .mode = "ffa",
                         .players = players,
                         .capacity = 16,
                         .last_tick_at = last_tick_at,
                         .overruns = overruns};
}

/// The SDK with a fake sidecar that answers every call `answer`, and a fake clock.
class Driven {
 public:
  explicit Driven(AgonesSdkConfig config = {}) : sdk(config) {}

  /// Runs the SDK to `until` in 10 ms steps, the matches ticking on time unless `stuck_since`
  /// (then their last tick stays there); every call made, in order, as "METHOD PATH BODY".
  std::vector<std::string> run_until(proto::TimeUs until, int players = 0,
                                     std::optional<proto::TimeUs> stuck_since = std::nullopt) {
    std::vector<std::string> calls;
    for (; now <= until; now += 10 * kMs) {
      sdk.observe({match_view(stuck_since ? *stuck_since : now, players, overruns)});
      while (auto call = sdk.next_call(now)) {
        calls.push_back(call->method + " " + call->path + " " + call->body);
        sdk.call_done(answer, now, call->path == "/gameserver" ? game_server_body : "{}");
      }
    }
    return calls;
  }

  static int count(const std::vector<std::string>& calls, const std::string& prefix) {
    int n = 0;
    for (const std::string& call : calls) n += call.rfind(prefix, 0) == 0 ? 1 : 0;
    return n;
  }

  AgonesSdk sdk;
  proto::TimeUs now = 1000 * kSecond;
  AgonesOutcome answer = AgonesOutcome::Ok;
  std::uint64_t overruns = 0;
  std::string game_server_body = R"({"status":{"state":"Ready"}})";
};

TEST(AgonesSdk, NothingIsSentBeforeTheServerIsReady) {
  Driven driven;
  EXPECT_TRUE(driven.run_until(driven.now + 5 * kSecond).empty());
  EXPECT_FALSE(driven.sdk.next_due(driven.now));
}

TEST(AgonesSdk, ReadyOnceThenLabelsThenAHealthPingEveryTwoSeconds) {
  Driven driven;
  driven.sdk.ready(driven.now);
  const proto::TimeUs start = driven.now;
  const auto calls = driven.run_until(start + 10 * kSecond - kMs);
  ASSERT_GE(calls.size(), 6u);
  EXPECT_EQ(calls[0], "POST /ready {}");
  EXPECT_EQ(calls[1], "POST /health {}");
  EXPECT_EQ(Driven::count(calls, "POST /ready"), 1);
  // 10 s: pings at 0, 2, 4, 6 and 8 s.
  EXPECT_EQ(Driven::count(calls, "POST /health {}"), 5);
  EXPECT_EQ(Driven::count(calls, "PUT /metadata/label {\"key\":\"map\",\"value\":\"arena\"}"), 1);
  EXPECT_EQ(Driven::count(calls, "PUT /metadata/label {\"key\":\"mode\",\"value\":\"ffa\"}"), 1);
  EXPECT_EQ(Driven::count(calls, "PUT /metadata/label {\"key\":\"players\",\"value\":\"0\"}"), 1);
  EXPECT_EQ(Driven::count(calls, "PUT /metadata/label {\"key\":\"capacity\",\"value\":\"16\"}"), 1);
  EXPECT_EQ(Driven::count(calls, "POST /allocate"), 0);
  EXPECT_TRUE(driven.sdk.is_ready());
}

TEST(AgonesSdk, AStuckMatchWithholdsThePingsUntilItTicksAgain) {
  Driven driven;
  driven.sdk.ready(driven.now);
  const proto::TimeUs start = driven.now;
  EXPECT_EQ(Driven::count(driven.run_until(start + 3 * kSecond), "POST /health"), 2);
  // The match's strand is blocked from 3 s: its last tick stays there.
  const proto::TimeUs stuck_at = driven.now;
  const auto stuck = driven.run_until(stuck_at + 10 * kSecond, 0, stuck_at);
  // The ping due at 4 s is 1 s after the last tick: on time by stuck_after_us; none after.
  EXPECT_LE(Driven::count(stuck, "POST /health"), 1);
  EXPECT_GE(driven.sdk.counters().health_withheld, 4u);
  // It ticks again: the next ping due goes.
  const auto resumed = driven.run_until(driven.now + 4 * kSecond);
  EXPECT_GE(Driven::count(resumed, "POST /health"), 2);
}

TEST(AgonesSdk, AMatchOverrunningItsCatchUpCapWithholdsAPing) {
  Driven driven;
  driven.sdk.ready(driven.now);
  const proto::TimeUs start = driven.now;
  driven.run_until(start + 2 * kSecond + 500 * kMs);  // pings at 0 and 2 s
  driven.overruns = 3;                                // between the pings of 2 and 4 s
  const auto calls = driven.run_until(start + 5 * kSecond);
  EXPECT_EQ(Driven::count(calls, "POST /health"), 0);
  EXPECT_EQ(driven.sdk.counters().health_withheld, 1u);
  // No further overruns: the next ping goes.
  EXPECT_EQ(Driven::count(driven.run_until(start + 7 * kSecond), "POST /health"), 1);
}

TEST(AgonesSdk, LabelsFollowThePlayersAtMostOncePerSecondWithTheLatestValue) {
  Driven driven;
  driven.sdk.ready(driven.now);
  const proto::TimeUs start = driven.now;
  driven.run_until(start + 100 * kMs);  // ready, health, the four labels
  // The players change every 10 ms for half a second: 1, 2, ... then stay at 7.
  std::vector<std::string> calls;
  for (int players = 1; players <= 7; ++players) {
    for (const auto& call : driven.run_until(driven.now + 50 * kMs, players)) {
      calls.push_back(call);
    }
  }
  for (const auto& call : driven.run_until(driven.now + 3 * kSecond, 7)) calls.push_back(call);
  const std::string players_label = "PUT /metadata/label {\"key\":\"players\"";
  // At most one per second after the first at 0 s: within 0.45..3.45 s, at most 3.
  EXPECT_LE(Driven::count(calls, players_label), 3);
  EXPECT_GE(Driven::count(calls, players_label), 1);
  std::string last;
  for (const auto& call : calls) {
    if (call.rfind(players_label, 0) == 0) last = call;
  }
  EXPECT_EQ(last, players_label + ",\"value\":\"7\"}");
}

TEST(AgonesSdk, TheFirstSeatedPlayerAllocatesOnce) {
  Driven driven;
  driven.sdk.ready(driven.now);
  EXPECT_EQ(Driven::count(driven.run_until(driven.now + kSecond, 0), "POST /allocate"), 0);
  const auto calls = driven.run_until(driven.now + 5 * kSecond, 2);
  EXPECT_EQ(Driven::count(calls, "POST /allocate {}"), 1);
  EXPECT_EQ(Driven::count(driven.run_until(driven.now + 5 * kSecond, 0), "POST /allocate"), 0);
}

TEST(AgonesSdk, GetsTheGameServerOnceReadyOnceAndHandsItsAnswerOver) {
  Driven driven;
  driven.sdk.fetch_game_server();
  driven.answer = AgonesOutcome::ServerError;  // the sidecar fails at first: both retried
  driven.sdk.ready(driven.now);
  EXPECT_EQ(Driven::count(driven.run_until(driven.now + kSecond), "GET"), 0);
  EXPECT_FALSE(driven.sdk.take_game_server());
  driven.answer = AgonesOutcome::Ok;
  const auto calls = driven.run_until(driven.now + 5 * kSecond);
  ASSERT_GE(calls.size(), 2u);
  EXPECT_EQ(calls[0], "POST /ready {}");
  EXPECT_EQ(calls[1], "GET /gameserver ");
  EXPECT_EQ(Driven::count(calls, "GET"), 1);
  const auto answer = driven.sdk.take_game_server();
  ASSERT_TRUE(answer);
  EXPECT_EQ(answer->body, std::optional<std::string>(driven.game_server_body));
  EXPECT_FALSE(driven.sdk.take_game_server());  // once
}

TEST(AgonesSdk, ARefusedGameServerCallIsHandedOverWithoutABody) {
  Driven driven;
  driven.sdk.fetch_game_server();
  driven.sdk.ready(driven.now);
  driven.answer = AgonesOutcome::ClientError;  // a 4xx settles a call as refused
  const auto calls = driven.run_until(driven.now + 10 * kMs);
  ASSERT_GE(calls.size(), 2u);
  EXPECT_EQ(calls[1], "GET /gameserver ");
  const auto answer = driven.sdk.take_game_server();
  ASSERT_TRUE(answer);
  EXPECT_FALSE(answer->body);
  EXPECT_EQ(Driven::count(driven.run_until(driven.now + 5 * kSecond), "GET"), 0);
}

TEST(AgonesSdk, NoGameServerCallUnlessAskedFor) {
  Driven driven;
  driven.sdk.ready(driven.now);
  EXPECT_EQ(Driven::count(driven.run_until(driven.now + 5 * kSecond), "GET"), 0);
}

TEST(AgonesSdk, ShutdownAfterDrainingAndNothingAfterIt) {
  Driven driven;
  driven.sdk.ready(driven.now);
  driven.run_until(driven.now + kSecond);
  driven.sdk.stopping();
  // While stopping the matches end: pings go on, no allocation, no labels.
  const auto stopping = driven.run_until(driven.now + 3 * kSecond, 3, driven.now);
  EXPECT_GE(Driven::count(stopping, "POST /health"), 1);
  EXPECT_EQ(Driven::count(stopping, "POST /allocate"), 0);
  EXPECT_EQ(Driven::count(stopping, "PUT"), 0);
  driven.sdk.drained();
  const auto calls = driven.run_until(driven.now + 5 * kSecond);
  ASSERT_FALSE(calls.empty());
  EXPECT_EQ(calls[0], "POST /shutdown {}");
  EXPECT_EQ(calls.size(), 1u);
  EXPECT_TRUE(driven.sdk.finished());
  EXPECT_FALSE(driven.sdk.next_due(driven.now));
}

TEST(AgonesSdk, ShutdownAfterTheConfiguredNumberOfFinishedMatches) {
  Driven driven({.shutdown_after_matches = 2});
  driven.sdk.ready(driven.now);
  driven.run_until(driven.now + kSecond);
  driven.sdk.match_finished();
  EXPECT_EQ(Driven::count(driven.run_until(driven.now + kSecond), "POST /shutdown"), 0);
  driven.sdk.match_finished();
  EXPECT_EQ(Driven::count(driven.run_until(driven.now + kSecond), "POST /shutdown {}"), 1);
  // The SIGTERM that follows drains the server: no second shutdown.
  driven.sdk.stopping();
  driven.sdk.drained();
  EXPECT_TRUE(driven.run_until(driven.now + kSecond).empty());
}

TEST(AgonesSdk, NeverShutsDownByMatchesWhenTheLimitIsZero) {
  Driven driven;
  driven.sdk.ready(driven.now);
  for (int i = 0; i < 50; ++i) driven.sdk.match_finished();
  EXPECT_EQ(Driven::count(driven.run_until(driven.now + kSecond), "POST /shutdown"), 0);
  EXPECT_EQ(driven.sdk.counters().matches_finished, 50u);
}

TEST(AgonesSdk, ALateSidecarGetsReadyRetriedWithBackOffUntilItAnswers) {
  Driven driven;
  driven.answer = AgonesOutcome::IoError;  // connection refused: the sidecar is not up yet
  driven.sdk.ready(driven.now);
  const proto::TimeUs start = driven.now;
  const auto refused = driven.run_until(start + 6 * kSecond);
  // Back-off 250, 500, 1000, 2000, 2000 ms: attempts at 0, 0.25, 0.75, 1.75, 3.75, 5.75 s.
  EXPECT_EQ(refused.size(), 6u);
  for (const auto& call : refused) EXPECT_EQ(call, "POST /ready {}");
  EXPECT_FALSE(driven.sdk.is_ready());
  driven.answer = AgonesOutcome::Ok;  // the sidecar is up
  const auto answered = driven.run_until(start + 8 * kSecond);
  ASSERT_FALSE(answered.empty());
  EXPECT_EQ(answered[0], "POST /ready {}");
  EXPECT_TRUE(driven.sdk.is_ready());
  const auto& ready = driven.sdk.counters().calls[static_cast<int>(AgonesCall::Ready)];
  EXPECT_EQ(ready[static_cast<int>(AgonesOutcome::IoError)], 6u);
  EXPECT_EQ(ready[static_cast<int>(AgonesOutcome::Ok)], 1u);
  // The back-off starts again from its first step after a success.
  driven.answer = AgonesOutcome::Timeout;
  driven.sdk.drained();
  const auto shutdown = driven.run_until(driven.now + 300 * kMs);
  EXPECT_EQ(Driven::count(shutdown, "POST /shutdown"), 2);
}

TEST(AgonesSdk, ASidecarAnswering500IsRetriedAndAnsweringAgainResumesThePings) {
  Driven driven;
  driven.sdk.ready(driven.now);
  driven.run_until(driven.now + kSecond);
  driven.answer = AgonesOutcome::ServerError;
  const auto failing = driven.run_until(driven.now + 5 * kSecond);
  // Pings retried every 2 s at most (the back-off's cap), never a pile-up.
  EXPECT_GE(Driven::count(failing, "POST /health"), 2);
  EXPECT_LE(failing.size(), 8u);
  const auto& health = driven.sdk.counters().calls[static_cast<int>(AgonesCall::Health)];
  EXPECT_EQ(health[static_cast<int>(AgonesOutcome::ServerError)], failing.size());
  driven.answer = AgonesOutcome::Ok;
  EXPECT_GE(Driven::count(driven.run_until(driven.now + 4 * kSecond), "POST /health"), 2);
}

TEST(AgonesSdk, ARefusedCallIsDroppedNotRetried) {
  Driven driven;
  driven.answer = AgonesOutcome::ClientError;
  driven.sdk.ready(driven.now);
  const auto calls = driven.run_until(driven.now + 500 * kMs);
  EXPECT_EQ(Driven::count(calls, "POST /ready"), 1);
  // Each label once: a 4xx value is not sent again until it changes.
  EXPECT_EQ(Driven::count(calls, "PUT /metadata/label"), 4);
}

TEST(AgonesSdk, OneCallInFlightAtATime) {
  AgonesSdk sdk;
  sdk.ready(0);
  sdk.observe({match_view(0)});
  ASSERT_TRUE(sdk.next_call(0));
  EXPECT_FALSE(sdk.next_call(0));
  EXPECT_FALSE(sdk.next_due(0));
  sdk.call_done(AgonesOutcome::Ok, 0);
  EXPECT_TRUE(sdk.next_call(0));
}

TEST(AgonesSdk, LabelValuesAreValidKubernetesLabelValues) {
  EXPECT_EQ(AgonesSdk::label_value("arena"), "arena");
  EXPECT_EQ(AgonesSdk::label_value("arena.foundry"), "arena.foundry");
  EXPECT_EQ(AgonesSdk::label_value("my map/ü"), "my-map");
  EXPECT_EQ(AgonesSdk::label_value("--x--"), "x");
  EXPECT_EQ(AgonesSdk::label_value(std::string(100, 'a')).size(), 63u);
  EXPECT_EQ(AgonesSdk::label_value("\"},{"), "");
}

TEST(AgonesSdk, SeveralMatchesJoinTheirMapsAndAddTheirSeats) {
  Driven driven;
  driven.sdk.ready(driven.now);
  AgonesMatchView other = match_view(driven.now, 3);
  other.id = 2;
  other.map = "foundry";
  driven.sdk.observe({match_view(driven.now, 2), other});
  std::vector<std::string> calls;
  while (auto call = driven.sdk.next_call(driven.now)) {
    calls.push_back(call->body);
    driven.sdk.call_done(AgonesOutcome::Ok, driven.now);
  }
  EXPECT_EQ(Driven::count(calls, "{\"key\":\"map\",\"value\":\"arena.foundry\"}"), 1);
  EXPECT_EQ(Driven::count(calls, "{\"key\":\"players\",\"value\":\"5\"}"), 1);
  EXPECT_EQ(Driven::count(calls, "{\"key\":\"capacity\",\"value\":\"32\"}"), 1);
}

}  // namespace
}  // namespace ricochet::server::agones_sdk_test
