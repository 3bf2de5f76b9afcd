/// Interpolated others and the predicted own player over the feed's view (rendered_view.h).

#include "ricochet/bot/rendered_view.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <variant>
#include <vector>

namespace ricochet::bot {

RenderedView::RenderedView(const wire::JoinMatchReply& reply, const proto::QuantizationSpec& spec,
                           std::string log_name)
    : interpolator_(reply.tick_rate_hz(), reply.snapshot_rate_hz()),
      rendered_(spec),
      log_name_(std::move(log_name)) {
  if (!reply.has_world()) {
    spdlog::info("{}: the join reply has no collision world; own player unpredicted", log_name_);
    return;
  }
  auto built = build_prediction_world(reply.world());
  if (auto* error = std::get_if<std::string>(&built)) {
    ++worlds_refused_;
    spdlog::warn("{}: collision world refused ({}); own player unpredicted", log_name_, *error);
    return;
  }
  predictor_.emplace(std::get<PredictionWorld>(std::move(built)), spec,
                     1.0f / static_cast<float>(reply.tick_rate_hz()));
}

void RenderedView::on_snapshot(const GameFeed& feed, double now_s) {
  const WorldView& view = feed.view();
  interpolator_.add(view.tick(), view.entities(), now_s);
  if (predictor_) {
    predictor_->reconcile(view.own(), feed.inputs().acknowledged(), feed.inputs().unacknowledged());
  }
}

const WorldView& RenderedView::render(const WorldView& latest, double now_s) {
  shown_at_ = interpolator_.advance(now_s);
  rendered_ = latest;
  if (shown_at_.tick == 0) return rendered_;
  std::vector<SeenEntity> entities = interpolator_.entities();
  // The own player as predicted (or as the newest snapshot has it), not as it was a delay ago.
  const std::uint32_t own_id = latest.own_id();
  const SeenEntity* newest_own = latest.own();
  std::optional<SeenEntity> own;
  if (predictor_ && predictor_->active()) {
    own = predictor_->own();
  } else if (newest_own) {
    own = *newest_own;
  }
  std::erase_if(entities, [own_id](const SeenEntity& e) { return e.id == own_id; });
  if (own) {
    own->id = own_id;
    const auto at =
        std::lower_bound(entities.begin(), entities.end(), own_id,
                         [](const SeenEntity& e, std::uint32_t id) { return e.id < id; });
    entities.insert(at, *own);
  }
  rendered_.show(shown_at_.tick, std::move(entities));
  return rendered_;
}

void RenderedView::stamp(wire::Input& input) const {
  if (shown_at_.tick == 0) return;
  input.set_view_tick(shown_at_.tick);
  input.set_view_fraction(shown_at_.fraction);
}

void RenderedView::on_input(const wire::Input& sent) {
  if (predictor_) predictor_->apply(sent);
}

void RenderedView::add_to(BotMetrics& out) const {
  out.worlds_refused += worlds_refused_;
  if (!predictor_) return;
  const PredictionStats& stats = predictor_->stats();
  out.prediction_error_m.insert(out.prediction_error_m.end(), stats.errors_m.begin(),
                                stats.errors_m.end());
  out.prediction_resets += stats.resets;
  out.prediction_replayed += stats.replayed;
  out.own_travelled_m += stats.travelled_m;
}

}  // namespace ricochet::bot
