#pragma once
/// The server's configuration as every match's config: [game] gives the tick and the snapshots,
/// [matches] the rules, the weapons' self damage and friendly fire, lag compensation and
/// recording. ServerConfig::validate() has checked the ranges, which are MatchConfig's.

#include "ricochet/server/config.h"
#include "ricochet/server/match_config.h"

namespace ricochet::server {

/// id, name and max_players are the registry's, per match. matches.seed 0 stays 0: the registry
/// draws a seed for each match when it opens (MatchRegistryConfig).
MatchConfig match_defaults(const ServerConfig& config);

}  // namespace ricochet::server
