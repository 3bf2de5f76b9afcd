#pragma once
/// A real recording for the web tests: four players on server/maps/arena.toml (so the
/// recording's map files parse back), each aiming at the next (rifle, then rockets) and strafing,
/// recorded by the Match itself as the server records it.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "ricochet/proto/entity_flags.h"
#include "ricochet/server/map.h"
#include "ricochet/server/match.h"

namespace ricochet::server::web_test {

/// The finished recording's bytes after `ticks` steps; every Kill event of the match appended
/// to `kills` when given (what the players were told, to compare a replay with).
inline std::vector<std::uint8_t> scripted_recording(int ticks = 900,
                                                    std::vector<wire::Kill>* kills = nullptr) {
  auto map = load_map_file(RICOCHET_SOURCE_DIR "/server/maps/arena.toml");
  EXPECT_TRUE(std::holds_alternative<Map>(map));
  MatchConfig config;
  config.rules.min_players = 2;
  config.rules.warmup_s = 0.2f;
  config.rules.respawn_delay_s = 0.5f;
  config.rules.frag_limit = 0;
  config.rules.seed = 5;
  config.hash_interval_ticks = 30;
  auto created = Match::create(config, std::get<Map>(map), 1'000'000);
  EXPECT_TRUE(std::holds_alternative<Match>(created));
  Match match = std::get<Match>(std::move(created));
  if (kills) {
    match.observe_events([kills](const wire::GameEvent& event) {
      if (event.has_kill()) kills->push_back(event.kill());
    });
  }
  proto::TimeUs now = 1'000'000;
  std::uint32_t sequence[5] = {};
  for (int tick = 0; tick < ticks; ++tick) {
    static const char* const kNames[] = {"ann", "ben", "cid", "dee"};
    if (tick < 4) match.connect(static_cast<std::uint64_t>(tick + 1), kNames[tick]);
    for (std::uint64_t account = 1; account <= 4; ++account) {
      const auto me = match.entity_of(account);
      const auto target = match.entity_of(account % 4 + 1);
      if (!me || !target) continue;
      std::array<float, 3> from{}, to{};
      for (const proto::EntityState& state : match.entity_states()) {
        if (state.id == *me) from = state.position_m;
        if (state.id == *target) to = state.position_m;
      }
      wire::ClientPayload payload;
      wire::Input& in = *payload.add_inputs();
      in.set_sequence(++sequence[account]);
      in.set_yaw(std::atan2(-(to[0] - from[0]), -(to[2] - from[2])));
      in.set_move_right(tick % 120 < 60 ? 100 : -100);
      in.set_weapon_slot(tick % 300 < 200 ? 1 : 2);  // rifle, then rockets
      in.set_buttons(tick % 6 < 3 ? proto::kButtonFire : 0u);
      in.set_view_tick(match.tick_number());
      std::vector<std::uint8_t> bytes(payload.ByteSizeLong());
      payload.SerializeToArray(bytes.data(), static_cast<int>(bytes.size()));
      match.receive(account, bytes);
      match.set_latency(account, 10'000);
    }
    now += proto::kMicrosPerSecond / 60 + 1;
    match.tick(now);
    Outgoing out;
    while (match.poll_outbox(out)) {
    }
  }
  return match.take_recording();
}

}  // namespace ricochet::server::web_test
