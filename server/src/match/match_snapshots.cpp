/// A match's snapshots and the send phase (match_snapshots.h).

#include "match_snapshots.h"

#include <utility>

namespace ricochet::server {

namespace {

/// ServerPayload fields around the snapshot: three uint32 (tag + up to 5 bytes each), the
/// snapshot's tag and length (1 + 2 bytes) and the PlayerStatus (at most 2 + 45 bytes: five
/// small ints, three ammo counts, two ticks), so the whole payload stays within the budget.
constexpr std::size_t kPayloadOverheadBytes = 3 * 6 + 3 + 47;

std::array<float, 3> to_array(const physics::Vec3& v) {
  return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
}

}  // namespace

void build_snapshots(std::uint32_t tick, std::span<const proto::EntityState> states,
                     const proto::QuantizationSpec& spec, std::size_t budget_bytes, Roster& roster,
                     Snapshots& snapshots) {
  snapshots.quantized.resize(states.size());
  for (std::size_t k = 0; k < states.size(); ++k) {
    snapshots.quantized[k] = proto::quantize(states[k], spec);
  }
  snapshots.payload_count = 0;
  for (Player& player : roster.players) {
    if (!player.connected) continue;
    if (snapshots.payload_count == snapshots.payloads.size()) snapshots.payloads.emplace_back();
    AddressedPayload& addressed = snapshots.payloads[snapshots.payload_count++];
    addressed.account = player.account;
    wire::ServerPayload& payload = addressed.payload;
    if (player.snapshot_ack != 0)
      player.snapshots->acknowledge(std::exchange(player.snapshot_ack, 0));
    player.snapshots->encode(tick, snapshots.quantized, to_array(player.position_m),
                             budget_bytes - kPayloadOverheadBytes, *payload.mutable_snapshot(),
                             snapshots.cache);
    payload.set_last_input_sequence(player.inputs.last_applied_sequence());
    payload.set_server_tick(tick);
    payload.set_your_entity_id(player.entity_id);
    wire::PlayerStatus& status = *payload.mutable_status();
    status.set_health(player.vitals.health);
    status.set_armor(player.vitals.armor);
    status.set_weapon(to_wire(player.weapon));
    status.clear_ammo();
    for (const int rounds : player.ammo) status.add_ammo(rounds);
    status.set_alive(player.alive);
    status.set_respawn_tick(player.alive ? 0 : player.respawn_tick);
    status.set_protected_until_tick(player.protected_until);
    status.set_team(static_cast<wire::Team>(player.team));
  }
}

void send(Snapshots& snapshots, Mailbox& mailbox, MatchCounters& counters) {
  // Events first: a PlayerJoined arrives no later than the first snapshot showing the entity
  // on a link without loss.
  counters.events_sent += mailbox.deliver_pending();
  for (std::size_t k = 0; k < snapshots.payload_count; ++k) {
    const AddressedPayload& addressed = snapshots.payloads[k];
    Outgoing out;
    out.account = addressed.account;
    out.reliable = false;
    out.bytes.resize(addressed.payload.ByteSizeLong());
    addressed.payload.SerializeToArray(out.bytes.data(), static_cast<int>(out.bytes.size()));
    counters.snapshot_bytes += out.bytes.size();
    ++counters.snapshots_sent;
    mailbox.outbox.push_back(std::move(out));
  }
  snapshots.payload_count = 0;
}

}  // namespace ricochet::server
