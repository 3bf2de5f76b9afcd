/// What a server reads from the world each tick without a BodyState per body: the live bodies,
/// their state in bulk into caller-provided spans, and the bodies that moved in the last step
/// (move events, after Box2D's b2World_GetBodyEvents).

#include <string>

#include "world_impl.h"

namespace ricochet::physics {

std::uint32_t World::live_bodies(std::span<BodyId> out) const {
  const BodyStore& b = impl_->state.bodies;
  std::size_t written = 0;
  for (std::uint32_t s = 0; s < b.slot_count() && written < out.size(); ++s) {
    if (b.alive(s)) out[written++] = b.id_of(s);
  }
  return b.slots.alive_count;
}

Status World::read_bodies(std::span<const BodyId> ids, const BodyReadout& out) const {
  const BodyStore& b = impl_->state.bodies;
  const auto check_size = [&](const char* name, std::size_t size) -> std::string {
    if (size == 0 || size == ids.size()) return {};
    return std::string("read_bodies: out.") + name + " holds " + std::to_string(size) +
           " elements for " + std::to_string(ids.size()) + " ids; pass an empty span or one of " +
           std::to_string(ids.size());
  };
  for (const std::string& e : {
           check_size("positions", out.positions.size()),
           check_size("orientations", out.orientations.size()),
           check_size("linear_velocities", out.linear_velocities.size()),
           check_size("angular_velocities", out.angular_velocities.size()),
           check_size("user_data", out.user_data.size()),
       }) {
    if (!e.empty()) return Error{ErrorCode::InvalidArgument, e};
  }
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (!b.valid(ids[i])) {
      return Error{ErrorCode::InvalidHandle,
                   "read_bodies: ids[" + std::to_string(i) + "] = BodyId{" +
                       std::to_string(ids[i].index) + ", generation " +
                       std::to_string(ids[i].generation) +
                       "} is null, stale or unknown; nothing was written"};
    }
  }
  // One pass per field: each writes one contiguous output from one array of the store.
  for (std::size_t i = 0; i < out.positions.size(); ++i)
    out.positions[i] = b.position[ids[i].index];
  for (std::size_t i = 0; i < out.orientations.size(); ++i)
    out.orientations[i] = b.orientation[ids[i].index];
  for (std::size_t i = 0; i < out.linear_velocities.size(); ++i)
    out.linear_velocities[i] = b.motion[ids[i].index].linear_velocity;
  for (std::size_t i = 0; i < out.angular_velocities.size(); ++i)
    out.angular_velocities[i] = b.motion[ids[i].index].angular_velocity;
  for (std::size_t i = 0; i < out.user_data.size(); ++i)
    out.user_data[i] = b.user_data[ids[i].index];
  return {};
}

std::span<const BodyMoveEvent> World::body_move_events() const {
  return impl_->events.body_moves;
}

void WorldImpl::mark_for_move_event(std::uint32_t slot, std::uint8_t why) {
  query_grid.mark_stale();
  if (events.move_marks.size() <= slot) events.move_marks.resize(state.bodies.slot_count(), 0);
  std::uint8_t& mark = events.move_marks[slot];
  if (mark == 0) events.marked_slots.push_back(slot);
  // A new body in a reused slot keeps nothing of the last one's marks.
  mark = why == kMoveMarkCreated ? kMoveMarkMoved : static_cast<std::uint8_t>(mark | why);
}

void WorldImpl::report_body_moves() {
  const BodyStore& b = state.bodies;
  const std::vector<std::uint32_t>& awake = scratch.awake_list;  // ascending
  const auto report = [&](std::uint32_t s, bool was_awake, std::uint8_t mark) {
    const bool fell_asleep = was_awake && b.has(s, kFlagSleeping);
    const bool moved =
        (mark & kMoveMarkMoved) != 0 ||
        (was_awake &&
         ((b.position[s].array() != scratch.start_position[s].array()).any() ||
          (b.orientation[s].coeffs().array() != scratch.start_orientation[s].coeffs().array())
              .any()));
    const bool woke = (mark & kMoveMarkWoke) != 0;
    if (!moved && !woke && !fell_asleep) return;
    events.body_moves.push_back(
        {b.id_of(s), b.position[s], b.orientation[s], b.user_data[s], fell_asleep, woke});
  };
  if (events.marked_slots.empty()) {
    for (const std::uint32_t s : awake) report(s, true, 0);  // every mark is 0
  } else {  // a body marked between steps (moved, restored) may be asleep: visit every slot
    std::size_t next = 0;
    for (std::uint32_t s = 0; s < b.slot_count(); ++s) {
      const bool was_awake = next < awake.size() && awake[next] == s;
      next += was_awake ? 1 : 0;
      if (b.alive(s)) report(s, was_awake, s < events.move_marks.size() ? events.move_marks[s] : 0);
    }
  }
  for (const std::uint32_t s : events.marked_slots) events.move_marks[s] = 0;
  events.marked_slots.clear();
}

}  // namespace ricochet::physics
