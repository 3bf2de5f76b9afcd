#pragma once
/// A match's reliable events on their way out (match.h): queued to one account or broadcast to
/// the connected players, held until the tick's send phase, then in the outbox with the
/// snapshots until the server drains it.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "ricochet/server/match.h"
#include "ricochet/wire/game.pb.h"
#include "roster.h"

namespace ricochet::server {

struct Mailbox {
  std::vector<Outgoing> pending;  ///< reliable GameEvents, moved to the outbox by send
  std::vector<Outgoing> outbox;   ///< what poll_outbox hands out, oldest first
  std::size_t outbox_read = 0;    ///< of outbox: taken so far
  /// Told every broadcast event once, connected players or not (Match::observe_events).
  std::function<void(const wire::GameEvent&)> observer;

  /// Serialises `event` for `account`.
  void queue(std::uint64_t account, const wire::GameEvent& event,
             proto::Delivery delivery = proto::Delivery::MustArrive);
  /// Queues `event` to every connected player of `roster`.
  void broadcast(const Roster& roster, const wire::GameEvent& event,
                 proto::Delivery delivery = proto::Delivery::MustArrive);
  /// Forgets the events queued for `account`: its connection is gone or replaced.
  void drop(std::uint64_t account);
  /// Tells `account` that `other` is in the match (a PlayerJoined).
  void queue_present(std::uint64_t account, const Player& other);
  /// Moves the pending events to the outbox; returns how many.
  std::size_t deliver_pending();
  bool poll(Outgoing& out);
  std::size_t size() const { return outbox.size() - outbox_read; }
  /// Forgets everything: nobody listens to a replay.
  void clear();
};

}  // namespace ricochet::server
