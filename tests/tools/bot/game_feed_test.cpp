#include "ricochet/bot/game_feed.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "ricochet/proto/snapshot_codec.h"

namespace ricochet::bot::game_feed_test {
namespace {

std::span<const std::uint8_t> bytes_of(const std::string& text) {
  return {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()};
}

/// A server's end: encodes the world for one client as the match does.
class FakeServer {
 public:
  FakeServer() : encoder_(proto::QuantizationSpec{}) {}
  std::string payload(std::uint32_t tick, std::uint32_t last_input = 0) {
    std::vector<proto::QuantizedEntity> world;
    for (std::uint32_t id = 1; id <= 3; ++id) {
      proto::EntityState state;
      state.id = id;
      state.position_m = {static_cast<float>(id), 1.0f, static_cast<float>(tick) * 0.01f};
      world.push_back(proto::quantize(state, encoder_.spec()));
    }
    wire::ServerPayload out;
    encoder_.encode(tick, world, {0, 0, 0}, 1100, *out.mutable_snapshot());
    out.set_server_tick(tick);
    out.set_your_entity_id(1);
    out.set_last_input_sequence(last_input);
    out.mutable_status()->set_alive(true);
    return out.SerializeAsString();
  }
  void acknowledge(std::uint32_t tick) { encoder_.acknowledge(tick); }

 private:
  proto::SnapshotEncoder encoder_;
};

TEST(GameFeed, DecodesSnapshotsAndAcknowledgesTheNewest) {
  FakeServer server;
  GameFeed feed(proto::QuantizationSpec{}, 1.0, "test");
  ASSERT_TRUE(feed.read_payload(bytes_of(server.payload(10))));
  EXPECT_EQ(feed.own_entity_id(), 1u);
  EXPECT_EQ(feed.view().entities().size(), 3u);
  ASSERT_NE(feed.view().own(), nullptr);
  EXPECT_TRUE(feed.status().alive());

  wire::ClientPayload sent;
  ASSERT_TRUE(sent.ParseFromString(feed.write_payload({})));
  EXPECT_EQ(sent.ack_snapshot_tick(), 10u);
  ASSERT_EQ(sent.inputs_size(), 1);
  EXPECT_EQ(sent.inputs(0).sequence(), 1u);
  EXPECT_EQ(sent.inputs(0).view_tick(), 10u);

  server.acknowledge(10);
  ASSERT_TRUE(feed.read_payload(bytes_of(server.payload(12, 1))));  // a delta; tick 11 lost
  EXPECT_EQ(feed.inputs().acknowledged(), 1u);
  EXPECT_EQ(feed.gaps().lost(), 1u);
  EXPECT_EQ(feed.counts().snapshots, 2u);
  EXPECT_EQ(feed.counts().bad_payloads, 0u);
}

TEST(GameFeed, RefusesWhatMakesNoSenseAndCountsIt) {
  FakeServer server;
  GameFeed feed(proto::QuantizationSpec{}, 1.0, "test");
  EXPECT_FALSE(feed.read_payload(bytes_of(std::string("\xff\xff\xff", 3))));
  EXPECT_EQ(feed.counts().bad_payloads, 1u);

  wire::ServerPayload mismatch;
  ASSERT_TRUE(mismatch.ParseFromString(server.payload(5)));
  mismatch.set_server_tick(6);
  EXPECT_FALSE(feed.read_payload(bytes_of(mismatch.SerializeAsString())));
  EXPECT_EQ(feed.counts().bad_payloads, 2u);

  const std::string seven = server.payload(7);
  EXPECT_TRUE(feed.read_payload(bytes_of(seven)));
  EXPECT_FALSE(feed.read_payload(bytes_of(seven)));  // a duplicate: stale
  EXPECT_EQ(feed.counts().snapshots_refused, 1u);
  // An acknowledgement of an input never sent is counted; the snapshot is still used.
  EXPECT_TRUE(feed.read_payload(bytes_of(server.payload(8, 99))));
  EXPECT_EQ(feed.counts().bad_payloads, 3u);

  EXPECT_FALSE(feed.read_event(bytes_of("")));  // no event set
  EXPECT_FALSE(feed.read_event(bytes_of(std::string("\x0a\xff", 2))));
  EXPECT_EQ(feed.counts().bad_events, 2u);
  wire::GameEvent kill;
  kill.mutable_kill()->set_victim_entity_id(2);
  const auto read = feed.read_event(bytes_of(kill.SerializeAsString()));
  ASSERT_TRUE(read);
  EXPECT_EQ(read->kill().victim_entity_id(), 2u);
}

TEST(GameFeed, RandomAndCorruptedBytesAreCountedNeverTrusted) {
  FakeServer server;
  GameFeed feed(proto::QuantizationSpec{}, 1.0, "test");
  std::mt19937 random(1234);
  std::vector<std::string> valid;
  for (std::uint32_t tick = 1; tick <= 50; ++tick) valid.push_back(server.payload(tick));
  wire::GameEvent spawned;
  spawned.mutable_spawned()->set_entity_id(2);
  for (const float v : {1.0f, 2.0f, 3.0f}) spawned.mutable_spawned()->add_position(v);
  valid.push_back(spawned.SerializeAsString());
  for (int i = 0; i < 20000; ++i) {
    std::string bytes = valid[random() % valid.size()];
    if (i % 2) {
      bytes.resize(random() % 64);
      for (char& c : bytes) c = static_cast<char>(random());
    } else {
      for (int flips = 1 + random() % 4; flips > 0 && !bytes.empty(); --flips) {
        bytes[random() % bytes.size()] ^= static_cast<char>(1u << (random() % 8));
      }
    }
    feed.read_payload(bytes_of(bytes));
    feed.read_event(bytes_of(bytes));
    feed.write_payload({});
  }
  const FeedCounts& counts = feed.counts();
  EXPECT_GT(counts.bad_payloads + counts.snapshots_refused, 0u);
  EXPECT_GT(counts.bad_events, 0u);
  for (const SeenEntity& entity : feed.view().entities()) {
    for (const float v : entity.position_m) EXPECT_TRUE(std::isfinite(v));
  }
}

}  // namespace
}  // namespace ricochet::bot::game_feed_test
