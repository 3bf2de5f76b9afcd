/// SnapshotEncodeCache: many clients of one world, encoded once with a shared cache and once
/// without; every snapshot and report must be the same bytes and numbers.

#include <gtest/gtest.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <random>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "ricochet/proto/snapshot_codec.h"
#include "snapshot_test_world.h"

namespace ricochet::proto::snapshot_cache_test {
namespace {

struct Client {
  SnapshotEncoder plain;
  SnapshotEncoder cached;
  std::uint32_t ack_delay_ticks = 0;
  std::size_t budget_bytes = 0;
  std::array<float, 3> viewer_m{};
};

/// `count` clients of `spec`, each set up by `setup(index, client)`.
template <class Setup>
std::vector<Client> make_clients(const QuantizationSpec& spec, int count, Setup setup) {
  std::vector<Client> clients;
  for (int k = 0; k < count; ++k) {
    Client client{SnapshotEncoder(spec), SnapshotEncoder(spec), 0, 0, {}};
    setup(k, client);
    clients.push_back(std::move(client));
  }
  return clients;
}

/// One tick of one client on both encoders: the acknowledgement unless it is lost (one in
/// `loss_one_in`), then both encodes, whose bytes and reports must agree.
void encode_both(Client& client, std::uint32_t tick, const std::vector<QuantizedEntity>& world,
                 SnapshotEncodeCache& cache, std::mt19937& random, unsigned loss_one_in) {
  if (tick > client.ack_delay_ticks && random() % loss_one_in != 0) {
    client.plain.acknowledge(tick - client.ack_delay_ticks);
    client.cached.acknowledge(tick - client.ack_delay_ticks);
  }
  wire::Snapshot plain_out, cached_out;
  client.plain.encode(tick, world, client.viewer_m, client.budget_bytes, plain_out);
  client.cached.encode(tick, world, client.viewer_m, client.budget_bytes, cached_out, cache);
  std::string plain_bytes, cached_bytes;
  ASSERT_TRUE(plain_out.SerializeToString(&plain_bytes));
  ASSERT_TRUE(cached_out.SerializeToString(&cached_bytes));
  ASSERT_EQ(plain_bytes, cached_bytes) << "tick " << tick;
  const SnapshotEncodeReport& a = client.plain.last_report();
  const SnapshotEncodeReport& b = client.cached.last_report();
  ASSERT_EQ(a.has_baseline, b.has_baseline);
  ASSERT_EQ(a.baseline_tick, b.baseline_tick);
  ASSERT_EQ(a.entities, b.entities);
  ASSERT_EQ(a.pending, b.pending);
  ASSERT_EQ(a.sent, b.sent);
  ASSERT_EQ(a.deferred, b.deferred);
  ASSERT_EQ(a.bytes, b.bytes);
}

/// Entities move, join and leave; clients in groups acknowledge at the same delay (so they share
/// baselines), some lose acknowledgements, budgets go from tight (entities deferred) to roomy.
TEST(SnapshotEncodeCache, CachedEncodesWriteExactlyTheUncachedBytes) {
  const QuantizationSpec spec = test::test_spec();
  std::mt19937 random(20261201);
  std::vector<QuantizedEntity> world = test::random_world(120, spec, random);
  std::vector<Client> clients = make_clients(spec, 16, [](int k, Client& client) {
    client.ack_delay_ticks = static_cast<std::uint32_t>(1 + k % 3 * 2);
    client.budget_bytes = k % 4 == 3 ? 200 : 1100;
    client.viewer_m = {static_cast<float>(k % 5) * 10 - 20, 1, static_cast<float>(k % 7) * 8 - 24};
  });
  SnapshotEncodeCache cache;
  std::uint32_t next_id = 1000;
  for (std::uint32_t tick = 1; tick <= 300; ++tick) {
    if (tick % 50 != 0) {  // every 50th tick nothing moves
      test::perturb(world, spec, random);
      if (tick % 3 == 0) test::teleport(world, spec, random);
      if (random() % 10 == 0)
        world.erase(world.begin() + static_cast<std::ptrdiff_t>(random() % world.size()));
      if (random() % 10 == 0) world.push_back(test::random_entity(next_id++, spec, random, true));
    }
    for (Client& client : clients) {
      ASSERT_NO_FATAL_FAILURE(encode_both(client, tick, world, cache, random, 8));
    }
  }
  // The scene exercises both paths.
  EXPECT_GT(cache.hits(), 1000u);
  EXPECT_GT(cache.misses(), 300u);
}

/// A crowded world (entities spawning every tick) against budgets that just miss it: every
/// client leaves a few changed and new entities out, each its own by distance, so later
/// baselines are one world with exceptions per client and follow the walk against that world.
TEST(SnapshotEncodeCache, ClientsHoldingAWorldButAFewEntitiesFollowOneWalkAndWriteTheSameBytes) {
  const QuantizationSpec spec = test::test_spec();
  std::mt19937 random(20261202);
  std::vector<QuantizedEntity> world = test::random_world(140, spec, random);
  std::vector<Client> clients = make_clients(spec, 24, [](int k, Client& client) {
    client.ack_delay_ticks = k < 20 ? 6 : 9;  // two groups of one baseline age each
    client.budget_bytes = 700 + 40 * static_cast<std::size_t>(k % 5);
    client.viewer_m = {static_cast<float>(k % 6) * 12 - 30, 1, static_cast<float>(k % 4) * 16 - 24};
  });
  SnapshotEncodeCache cache;
  std::uint32_t next_id = 1000;
  std::uint64_t deferred = 0;
  for (std::uint32_t tick = 1; tick <= 240; ++tick) {
    test::perturb(world, spec, random);
    for (int spawn = 0; spawn < 3; ++spawn) {
      world.push_back(test::random_entity(next_id++, spec, random, false));
    }
    while (world.size() > 150) {
      world.erase(world.begin() + static_cast<std::ptrdiff_t>(random() % world.size()));
    }
    for (Client& client : clients) {
      ASSERT_NO_FATAL_FAILURE(encode_both(client, tick, world, cache, random, 16));
      deferred += client.plain.last_report().deferred;
    }
  }
  EXPECT_GT(deferred, 24u * 100u);  // the budgets did leave entities out
  EXPECT_GT(cache.walks_followed(), cache.misses() / 2);
}

/// Clients whose baseline is a whole world (every fourth tick is roomy, and they acknowledge two
/// ticks late) but whose last encode left entities out: the first of them on a tight tick keeps
/// its start, and the others start from it with their own carried priorities and viewers.
TEST(SnapshotEncodeCache, BoundClientsHoldingTheWholeWorldWeighTheirOwnCarriedPriorities) {
  const QuantizationSpec spec = test::test_spec();
  std::mt19937 random(20261204);
  std::vector<QuantizedEntity> world = test::random_world(120, spec, random);
  std::vector<Client> clients = make_clients(spec, 16, [](int k, Client& client) {
    client.ack_delay_ticks = 2;
    client.viewer_m = {static_cast<float>(k % 4) * 14 - 21, 1, static_cast<float>(k / 4) * 14 - 21};
  });
  SnapshotEncodeCache cache;
  std::uint64_t deferred = 0;
  for (std::uint32_t tick = 1; tick <= 200; ++tick) {
    test::perturb(world, spec, random);
    for (Client& client : clients) {
      client.budget_bytes = tick % 4 == 0 ? 1100 : 260 + 8 * (tick % 3);
      ASSERT_NO_FATAL_FAILURE(encode_both(client, tick, world, cache, random, 1u << 30));
      deferred += client.plain.last_report().deferred;
    }
  }
  EXPECT_GT(deferred, 16u * 100u);
  EXPECT_GT(cache.walks_followed(), 16u * 50u);
}

TEST(SnapshotEncodeCache, EachLayerIsSwitchedOffByItsNameAndAllByAll) {
  const auto off = [](std::string_view name) {
    SnapshotCacheLayers layers;
    EXPECT_TRUE(switch_off_cache_layer(name, layers)) << name;
    return std::array{layers.streams, layers.deltas, layers.world_baselines, layers.walks,
                      layers.whole_world_start};
  };
  EXPECT_EQ(off("streams"), (std::array{false, true, true, true, true}));
  EXPECT_EQ(off("deltas"), (std::array{true, false, true, true, true}));
  EXPECT_EQ(off("world_baselines"), (std::array{true, true, false, true, true}));
  EXPECT_EQ(off("walks"), (std::array{true, true, true, false, true}));
  EXPECT_EQ(off("whole_world_start"), (std::array{true, true, true, true, false}));
  EXPECT_EQ(off("all"), (std::array{false, false, false, false, false}));
  for (const std::string_view unknown : {"", "stream", "Streams", "all ", "walks,deltas"}) {
    SnapshotCacheLayers layers;
    EXPECT_FALSE(switch_off_cache_layer(unknown, layers)) << unknown;
    EXPECT_TRUE(layers.streams && layers.deltas && layers.world_baselines && layers.walks &&
                layers.whole_world_start)
        << unknown;
  }
}

/// Every layer switched off in turn (and all of them): the layers left on still write the
/// plain encoder's bytes, on a scene where budgets bind now and then and acknowledgements are
/// lost, so that every layer has work to do.
TEST(SnapshotEncodeCache, EachLayerSwitchedOffStillWritesTheUncachedBytes) {
  const QuantizationSpec spec = test::test_spec();
  const std::pair<const char*, SnapshotCacheLayers> variants[] = {
      {"streams off", {.streams = false}},
      {"deltas off", {.deltas = false}},
      {"world_baselines off", {.world_baselines = false}},
      {"walks off", {.walks = false}},
      {"whole_world_start off", {.whole_world_start = false}},
      {"all off", {false, false, false, false, false}},
  };
  for (const auto& [name, layers] : variants) {
    SCOPED_TRACE(name);
    std::mt19937 random(20261205);
    std::vector<QuantizedEntity> world = test::random_world(110, spec, random);
    std::vector<Client> clients = make_clients(spec, 12, [](int k, Client& client) {
      client.ack_delay_ticks = k < 8 ? 2 : 4;
      client.budget_bytes = k % 3 == 0 ? 1100 : 420 + 30 * static_cast<std::size_t>(k % 4);
      client.viewer_m = {static_cast<float>(k % 4) * 12 - 20, 1,
                         static_cast<float>(k % 3) * 16 - 16};
    });
    SnapshotEncodeCache cache(layers);
    std::uint32_t next_id = 1000;
    for (std::uint32_t tick = 1; tick <= 120; ++tick) {
      test::perturb(world, spec, random);
      if (tick % 2 == 0) world.push_back(test::random_entity(next_id++, spec, random, true));
      if (tick % 5 == 0)
        world.erase(world.begin() + static_cast<std::ptrdiff_t>(random() % world.size()));
      for (Client& client : clients) {
        ASSERT_NO_FATAL_FAILURE(encode_both(client, tick, world, cache, random, 12));
      }
    }
    EXPECT_EQ(cache.hits() > 0, layers.streams) << "streams shared only when on";
    EXPECT_EQ(cache.walks_followed() > 0, layers.walks && layers.deltas)
        << "walks followed only when on, with the layers they need";
  }
}

/// Clients whose baselines are a shared world but for exceptions, on the rare paths: encodes
/// that now and then go without the cache (the baseline is then made whole from the shared
/// world), and budgets too small for every removal of a tick that removes many at once (the view
/// is then merged from the baseline made whole).
TEST(SnapshotEncodeCache,
     WorldBaselinesMadeWholeWithoutTheCacheOrForDeferredRemovalsWriteTheSameBytes) {
  const QuantizationSpec spec = test::test_spec();
  std::mt19937 random(20261203);
  std::vector<QuantizedEntity> world = test::random_world(100, spec, random);
  std::vector<Client> clients = make_clients(spec, 12, [](int k, Client& client) {
    client.ack_delay_ticks = 2 + static_cast<std::uint32_t>(k % 2);
    client.budget_bytes = 300 + 100 * static_cast<std::size_t>(k % 4);
    client.viewer_m = {static_cast<float>(k % 4) * 12 - 20, 1, static_cast<float>(k % 3) * 16 - 16};
  });
  SnapshotEncodeCache cache;
  std::uint32_t next_id = 1000;
  for (std::uint32_t tick = 1; tick <= 200; ++tick) {
    test::perturb(world, spec, random);
    world.push_back(test::random_entity(next_id++, spec, random, false));
    // Now and then many removals at once, more than some clients' budgets hold that tick.
    const bool mass_removal = tick % 25 == 0;
    if (mass_removal) {
      for (int k = 0; k < 20; ++k) {
        world.erase(world.begin() + static_cast<std::ptrdiff_t>(random() % world.size()));
      }
    }
    for (std::size_t c = 0; c < clients.size(); ++c) {
      Client& client = clients[c];
      if (tick > client.ack_delay_ticks) {
        client.plain.acknowledge(tick - client.ack_delay_ticks);
        client.cached.acknowledge(tick - client.ack_delay_ticks);
      }
      const std::size_t budget_bytes = mass_removal && c % 3 == 0 ? 24 : client.budget_bytes;
      wire::Snapshot plain_out, cached_out;
      client.plain.encode(tick, world, client.viewer_m, budget_bytes, plain_out);
      if ((tick + c) % 7 == 0) {
        client.cached.encode(tick, world, client.viewer_m, budget_bytes, cached_out);
      } else {
        client.cached.encode(tick, world, client.viewer_m, budget_bytes, cached_out, cache);
      }
      std::string plain_bytes, cached_bytes;
      ASSERT_TRUE(plain_out.SerializeToString(&plain_bytes));
      ASSERT_TRUE(cached_out.SerializeToString(&cached_bytes));
      ASSERT_EQ(plain_bytes, cached_bytes) << "tick " << tick << " client " << c;
      ASSERT_EQ(client.plain.last_report().deferred, client.cached.last_report().deferred);
    }
  }
  EXPECT_GT(cache.walks_followed(), 500u);
}

}  // namespace
}  // namespace ricochet::proto::snapshot_cache_test
