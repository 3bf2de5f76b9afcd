#pragma once
/// Client-side prediction and reconciliation of the bot's own player (PROTOCOL.md Prediction and
/// reconciliation), sans-IO: a local physics world with the match's static geometry and one
/// sphere, the bot's own. Each own input moves it at once (the match's movement rules, one step
/// of the match's tick). On each snapshot the own entity's authoritative state replaces the
/// sphere's, the inputs the server has applied are dropped and the rest are replayed on top.
///
/// Prediction error: for the newest input a snapshot acknowledges, the distance between where
/// the bot had predicted that input to leave it and where the server says it is, before the
/// correction. The prediction is quantised to the snapshot's grid first, so quantisation alone
/// never counts: a server that applies the same inputs in the same world gives exactly 0.
///
/// Life events are not errors: while the own entity is dead, absent or away the predictor is
/// idle and shows the server's state; the first snapshot after (a respawn, a reconnect) and any
/// gap larger than kResetDistanceM (a teleport: three times the error bound of a bad mobile
/// link, tests/integration/bot_match_test.cpp) re-seed it from the server's state and count a
/// reset.

#include <cstddef>
#include <cstdint>
#include <deque>
#include <vector>

#include "ricochet/bot/collision_world.h"
#include "ricochet/bot/world_view.h"
#include "ricochet/proto/quantize.h"
#include "ricochet/wire/game.pb.h"

namespace ricochet::bot {

struct PredictionStats {
  std::vector<double> errors_m;   ///< one per newly acknowledged input, m (at most kMaxSamples)
  std::uint64_t resets = 0;       ///< re-seeds from the server's state (spawn, death, teleport)
  std::uint64_t replayed = 0;     ///< inputs replayed after corrections
  std::uint64_t corrections = 0;  ///< acknowledgements whose error was not 0
  double travelled_m = 0;  ///< how far the server moved the own player between snapshots (alive)
  static constexpr std::size_t kMaxSamples = 1u << 20;
};

class Predictor {
 public:
  /// A larger gap between prediction and server is a teleport (a reset), not an error, m.
  static constexpr double kResetDistanceM = 3.0;

  /// world: build_prediction_world()'s. spec: the join reply's (validated). tick_s: 1/rate.
  Predictor(PredictionWorld world, const proto::QuantizationSpec& spec, float tick_s);

  /// One own input (sequence set), applied at once: movement, then one step. Ignored while idle.
  void apply(const wire::Input& input);
  /// A decoded snapshot: `own` is the own entity in it (nullptr: not there); `acknowledged`
  /// its payload's last_input_sequence; `unacknowledged` the inputs sent after it, oldest first.
  void reconcile(const SeenEntity* own, std::uint32_t acknowledged,
                 const std::deque<wire::Input>& unacknowledged);

  /// True while predicting (the own player is alive and was seen).
  bool active() const { return active_; }
  /// The predicted own state (the last server state while idle).
  SeenEntity own() const;
  const PredictionStats& stats() const { return stats_; }

 private:
  struct Predicted {
    std::uint32_t sequence = 0;
    physics::Vec3 position;
  };
  void step(const wire::Input& input);
  void seed(const SeenEntity& own);

  PredictionWorld world_;
  proto::QuantizationSpec spec_;
  float tick_s_;
  physics::BodyId body_;
  bool active_ = false;
  SeenEntity last_server_{};
  Vec3 seed_position_{};              ///< the server's position the prediction was last seeded from
  std::deque<Predicted> predicted_;   ///< after each unacknowledged input, oldest first
  std::uint32_t measured_up_to_ = 0;  ///< the newest acknowledgement measured
  PredictionStats stats_;
};

/// The character intent of a wire input, with the server's own conversion (the move vector over
/// 127, shortened to length 1).
physics::CharacterIntent intent_of(const wire::Input& input);

}  // namespace ricochet::bot
