#include "ricochet/bot/game_feed.h"

#include <spdlog/spdlog.h>

namespace ricochet::bot {

GameFeed::GameFeed(const proto::QuantizationSpec& spec, double ticks_per_snapshot,
                   std::string log_name)
    : decoder_(spec), view_(spec), gaps_(ticks_per_snapshot), log_name_(std::move(log_name)) {}

bool GameFeed::read_payload(std::span<const std::uint8_t> bytes) {
  wire::ServerPayload& payload = incoming_;
  if (!payload.ParseFromArray(bytes.data(), static_cast<int>(bytes.size()))) {
    ++counts_.bad_payloads;
    spdlog::debug("{}: a payload of {} bytes is not a ServerPayload", log_name_, bytes.size());
    return false;
  }
  if (payload.has_snapshot() && payload.snapshot().tick() != payload.server_tick()) {
    ++counts_.bad_payloads;
    spdlog::debug("{}: snapshot tick {} is not server_tick {}", log_name_,
                  payload.snapshot().tick(), payload.server_tick());
    return false;
  }
  if (!inputs_.acknowledge(payload.last_input_sequence())) {
    ++counts_.bad_payloads;
    spdlog::debug("{}: the server acknowledged input {} of {} sent", log_name_,
                  payload.last_input_sequence(), inputs_.last_sequence());
  }
  own_entity_id_ = payload.your_entity_id();
  status_ = payload.status();
  if (!payload.has_snapshot()) return false;
  const proto::SnapshotDecodeResult decoded = decoder_.decode(payload.snapshot());
  if (!decoded.ok) {
    ++counts_.snapshots_refused;
    spdlog::debug("{}: snapshot {} refused ({}): {}", log_name_, payload.server_tick(),
                  name(decoded.reason), decoded.message);
    return false;
  }
  view_.apply_snapshot(decoded.tick, own_entity_id_, decoded.entities);
  gaps_.on_snapshot(decoded.tick);
  ++counts_.snapshots;
  return true;
}

std::optional<wire::GameEvent> GameFeed::read_event(std::span<const std::uint8_t> bytes) {
  wire::GameEvent event;
  if (!event.ParseFromArray(bytes.data(), static_cast<int>(bytes.size())) ||
      event.event_case() == wire::GameEvent::EVENT_NOT_SET) {
    ++counts_.bad_events;
    spdlog::debug("{}: a reliable message of {} bytes is not a GameEvent", log_name_, bytes.size());
    return std::nullopt;
  }
  view_.apply_event(event);
  return event;
}

const std::string& GameFeed::write_payload(wire::Input input) {
  // Unless the caller rendered something else (rendered_view.h), the bot shows the newest
  // snapshot as is: that is the view lag compensation rewinds to.
  if (input.view_tick() == 0) input.set_view_tick(view_.tick());
  inputs_.push(std::move(input));
  inputs_.fill(payload_);
  payload_.set_ack_snapshot_tick(decoder_.has_snapshot() ? decoder_.newest_tick() : 0);
  payload_.SerializeToString(&payload_bytes_);
  return payload_bytes_;
}

}  // namespace ricochet::bot
