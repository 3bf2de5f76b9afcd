/// A match's reliable events on their way out (mailbox.h).

#include "mailbox.h"

namespace ricochet::server {

void Mailbox::queue(std::uint64_t account, const wire::GameEvent& event, proto::Delivery delivery) {
  Outgoing out;
  out.account = account;
  out.reliable = true;
  out.delivery = delivery;
  out.bytes.resize(event.ByteSizeLong());
  event.SerializeToArray(out.bytes.data(), static_cast<int>(out.bytes.size()));
  pending.push_back(std::move(out));
}

void Mailbox::broadcast(const Roster& roster, const wire::GameEvent& event,
                        proto::Delivery delivery) {
  if (observer) observer(event);
  for (const Player& player : roster.players) {
    if (player.connected) queue(player.account, event, delivery);
  }
}

void Mailbox::drop(std::uint64_t account) {
  std::erase_if(pending, [account](const Outgoing& out) { return out.account == account; });
}

void Mailbox::queue_present(std::uint64_t account, const Player& other) {
  wire::GameEvent present;
  present.mutable_player_joined()->set_entity_id(other.entity_id);
  present.mutable_player_joined()->set_name(other.name);
  queue(account, present);
}

std::size_t Mailbox::deliver_pending() {
  const std::size_t count = pending.size();
  for (Outgoing& event : pending) outbox.push_back(std::move(event));
  pending.clear();
  return count;
}

bool Mailbox::poll(Outgoing& out) {
  if (outbox_read >= outbox.size()) {
    outbox.clear();
    outbox_read = 0;
    return false;
  }
  out = std::move(outbox[outbox_read++]);
  return true;
}

void Mailbox::clear() {
  outbox.clear();
  outbox_read = 0;
  pending.clear();
}

}  // namespace ricochet::server
