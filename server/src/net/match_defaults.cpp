#include "match_defaults.h"

namespace ricochet::server {

MatchConfig match_defaults(const ServerConfig& config) {
  MatchConfig out;
  out.tick.rate_hz = config.game.tick_rate_hz;
  out.tick.max_catch_up_steps = config.game.max_catch_up_steps;
  out.snapshot_rate_hz = config.snapshot_rate_hz();
  out.snapshot_budget_bytes = static_cast<std::size_t>(config.snapshot_budget_bytes());
  out.snapshot_cache_layers = config.snapshot_cache_layers().value_or(proto::SnapshotCacheLayers{});
  const MatchesConfig& matches = config.matches;
  RulesConfig& rules = out.rules;
  rules.mode = matches.mode == "tdm" ? GameMode::TeamDeathmatch : GameMode::FreeForAll;
  rules.min_players = matches.min_players;
  rules.warmup_s = static_cast<float>(matches.warmup_s);
  rules.frag_limit = matches.frag_limit;
  rules.time_limit_s = static_cast<float>(matches.time_limit_s);
  rules.respawn_delay_s = static_cast<float>(matches.respawn_delay_s);
  rules.spawn_protection_s = static_cast<float>(matches.spawn_protection_s);
  rules.seed = static_cast<std::uint64_t>(matches.seed);
  out.weapons.self_damage_scale = static_cast<float>(matches.self_damage);
  out.weapons.friendly_fire = matches.friendly_fire;
  out.lag.enabled = matches.lag_compensation;
  out.lag.max_rewind_ms = static_cast<float>(matches.max_rewind_ms);
  out.record = matches.record;
  return out;
}

}  // namespace ricochet::server
