// Every [matches] key lands on the field of MatchConfig it configures, and what the server's
// defaults (and any configuration validate() accepts at its limits) give is a valid MatchConfig.
#include "match_defaults.h"

#include <gtest/gtest.h>

namespace ricochet::server::match_defaults_test {
namespace {

TEST(MatchDefaults, EveryMatchesKeyLandsOnItsMatchConfigField) {
  ServerConfig config;
  config.game.tick_rate_hz = 30;
  config.game.max_catch_up_steps = 3;
  MatchesConfig& matches = config.matches;
  matches.mode = "tdm";
  matches.min_players = 4;
  matches.warmup_s = 5;
  matches.frag_limit = 50;
  matches.time_limit_s = 300;
  matches.respawn_delay_s = 3;
  matches.spawn_protection_s = 0.5;
  matches.self_damage = 0.25;
  matches.friendly_fire = true;
  matches.seed = 1234;
  matches.lag_compensation = false;
  matches.max_rewind_ms = 100;
  matches.record = false;
  config.game.snapshot_cache_off = "deltas";
  ASSERT_TRUE(config.validate().empty());

  const MatchConfig out = match_defaults(config);
  EXPECT_EQ(out.tick.rate_hz, 30);
  EXPECT_EQ(out.tick.max_catch_up_steps, 3);
  EXPECT_EQ(out.snapshot_rate_hz, 30);  // 0: the tick rate
  EXPECT_EQ(out.rules.mode, GameMode::TeamDeathmatch);
  EXPECT_EQ(out.rules.min_players, 4);
  EXPECT_EQ(out.rules.warmup_s, 5.0f);
  EXPECT_EQ(out.rules.frag_limit, 50);
  EXPECT_EQ(out.rules.time_limit_s, 300.0f);
  EXPECT_EQ(out.rules.respawn_delay_s, 3.0f);
  EXPECT_EQ(out.rules.spawn_protection_s, 0.5f);
  EXPECT_EQ(out.rules.seed, 1234u);
  EXPECT_EQ(out.weapons.self_damage_scale, 0.25f);
  EXPECT_TRUE(out.weapons.friendly_fire);
  EXPECT_FALSE(out.lag.enabled);
  EXPECT_EQ(out.lag.max_rewind_ms, 100.0f);
  EXPECT_FALSE(out.record);
  EXPECT_FALSE(out.snapshot_cache_layers.deltas);
  EXPECT_TRUE(out.snapshot_cache_layers.streams);
  EXPECT_EQ(out.validate(), "");
}

TEST(MatchDefaults, TheServersDefaultsAndTheLimitsOfEveryRangeMakeAValidMatch) {
  ServerConfig config;
  EXPECT_EQ(match_defaults(config).rules.mode, GameMode::FreeForAll);
  EXPECT_EQ(match_defaults(config).rules.seed, 0u);  // drawn per match by the registry
  EXPECT_EQ(match_defaults(config).validate(), "");
  MatchesConfig& matches = config.matches;
  matches.frag_limit = 0;  // no limit
  matches.time_limit_s = 0;
  matches.warmup_s = 0;
  matches.min_players = 1;
  matches.respawn_delay_s = 0;
  matches.spawn_protection_s = 0;
  matches.self_damage = 1;
  matches.max_rewind_ms = 0;
  ASSERT_TRUE(config.validate().empty());
  EXPECT_EQ(match_defaults(config).validate(), "");
  matches.frag_limit = 1'000;
  matches.time_limit_s = 86'400;
  matches.warmup_s = 600;
  matches.max_players = 64;
  matches.min_players = 64;
  matches.respawn_delay_s = 60;
  matches.spawn_protection_s = 10;
  matches.self_damage = 0;
  matches.max_rewind_ms = 250;
  ASSERT_TRUE(config.validate().empty());
  EXPECT_EQ(match_defaults(config).validate(), "");
}

}  // namespace
}  // namespace ricochet::server::match_defaults_test
