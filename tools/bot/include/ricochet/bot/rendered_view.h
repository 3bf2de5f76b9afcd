#pragma once
/// What a predicting bot shows and plays on, per game connection, sans-IO: the other entities
/// interpolated (interpolator.h), its own player predicted (predictor.h), both over the feed's
/// newest view (spawn points, pickups, teams, phase). Its inputs claim the interpolated render
/// time as their view tick, so lag compensation rewinds to what the bot aimed at.
///
/// Without a usable collision world in the join reply (none sent, or refused: logged and
/// counted in worlds_refused) the own player is shown as the server sent it, unpredicted.

#include <cstdint>
#include <optional>
#include <string>

#include "ricochet/bot/bot_metrics.h"
#include "ricochet/bot/game_feed.h"
#include "ricochet/bot/interpolator.h"
#include "ricochet/bot/predictor.h"
#include "ricochet/bot/world_view.h"
#include "ricochet/wire/control.pb.h"

namespace ricochet::bot {

class RenderedView {
 public:
  /// reply: checked (tick and snapshot rates in range); spec: its quantisation, validated.
  RenderedView(const wire::JoinMatchReply& reply, const proto::QuantizationSpec& spec,
               std::string log_name);

  /// After GameFeed::read_payload decoded a snapshot, at `now_s` (the bot's clock, s): buffer
  /// it, reconcile the own player.
  void on_snapshot(const GameFeed& feed, double now_s);
  /// The view to decide on at `now_s` (the bot's clock, s): `latest` with the others at the
  /// render time and the own player predicted.
  const WorldView& render(const WorldView& latest, double now_s);
  /// Claims the render time in `input` (view_tick, view_fraction).
  void stamp(wire::Input& input) const;
  /// The input just sent (numbered), predicted at once.
  void on_input(const wire::Input& sent);
  /// Adds the prediction figures to `out`.
  void add_to(BotMetrics& out) const;

  bool predicting() const { return predictor_.has_value(); }
  const Predictor* predictor() const { return predictor_ ? &*predictor_ : nullptr; }
  RenderTime render_time() const { return shown_at_; }

 private:
  Interpolator interpolator_;
  std::optional<Predictor> predictor_;
  std::uint64_t worlds_refused_ = 0;
  WorldView rendered_;
  RenderTime shown_at_;
  std::string log_name_;
};

}  // namespace ricochet::bot
