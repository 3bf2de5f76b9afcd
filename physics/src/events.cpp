/// Event reporting after a step: which contacts began, ended or carried impulse, and which
/// sensor pairs began or stopped overlapping. Reads this step's and last step's contacts.

#include <algorithm>
#include <iterator>

#include "math_util.h"
#include "world_impl.h"

namespace ricochet::physics {

void WorldImpl::report_events() {
  // Touching: the contact carried load this step, or the surfaces are within slop.
  const Real touch_gap = def.linear_slop;
  for (auto* list : {&state.pair_contacts, &state.static_contacts}) {
    for (Contact& c : *list) c.touching = c.max_normal_impulse > 0 || c.separation < touch_gap;
  }
  // Sensors: overlapping pairs this step, as sorted keys.
  std::swap(scratch.previous_sensor_overlaps, state.sensor_overlaps);
  state.sensor_overlaps.clear();
  for (const BodyPair& p : scratch.sensor_pairs) {
    const Real reach = state.bodies.radius[p.a] + state.bodies.radius[p.b];
    if ((state.bodies.position[p.b] - state.bodies.position[p.a]).squaredNorm() < reach * reach) {
      state.sensor_overlaps.push_back(pair_key(p.a, p.b));
    }
  }
  std::sort(state.sensor_overlaps.begin(), state.sensor_overlaps.end());
  if (!def.contact_events) {
    events.pending_end_events.clear();
    return;
  }
  // Copied, not moved: both buffers keep their capacity.
  events.end_events.assign(events.pending_end_events.begin(), events.pending_end_events.end());
  events.pending_end_events.clear();

  const auto other_of = [&](const Contact& c, bool pair) {
    return pair ? body_target(c.b) : shape_target(c.b);
  };
  for (int list = 0; list < 2; ++list) {
    const bool pair = list == 0;
    for (const Contact& c : pair ? state.pair_contacts : state.static_contacts) {
      if (!c.touching) continue;
      const BodyId body = state.bodies.id_of(c.a);
      const std::uint64_t user_data = state.bodies.user_data[c.a];
      if (!c.previously_touching) {
        events.begin_events.push_back({body, other_of(c, pair), c.point, c.normal,
                                       std::max(Real(0), -c.relative_velocity), user_data});
      }
      if (c.total_normal_impulse > 0) {
        events.impulse_events.push_back(
            {body, other_of(c, pair), c.point, c.normal, c.total_normal_impulse, user_data});
      }
    }
  }
  // Last step's touching contacts that are gone, then those that stopped touching.
  const std::size_t previous_pairs = scratch.previous_pair_contacts.size();
  for (std::size_t i = 0; i < scratch.previous_matched.size(); ++i) {
    const bool pair = i < previous_pairs;
    const Contact& old = pair ? scratch.previous_pair_contacts[i]
                              : scratch.previous_static_contacts[i - previous_pairs];
    if (old.touching && !scratch.previous_matched[i] && state.bodies.alive(old.a)) {
      events.end_events.push_back(
          {state.bodies.id_of(old.a), other_of(old, pair), state.bodies.user_data[old.a]});
    }
  }
  for (auto* list : {&state.pair_contacts, &state.static_contacts}) {
    const bool pair = list == &state.pair_contacts;
    for (const Contact& c : *list) {
      if (c.previously_touching && !c.touching)
        events.end_events.push_back(
            {state.bodies.id_of(c.a), other_of(c, pair), state.bodies.user_data[c.a]});
    }
  }
  // Sensor begin/end from the sorted key sets.
  const auto sensor_event_target = [&](std::uint64_t key, BodyId& body, ContactTarget& other) {
    body = state.bodies.id_of(static_cast<std::uint32_t>(key >> 32));
    other = body_target(static_cast<std::uint32_t>(key));
  };
  std::vector<std::uint64_t>& diff = scratch.sensor_difference;
  diff.clear();
  std::set_difference(state.sensor_overlaps.begin(), state.sensor_overlaps.end(),
                      scratch.previous_sensor_overlaps.begin(),
                      scratch.previous_sensor_overlaps.end(), std::back_inserter(diff));
  for (const std::uint64_t key : diff) {
    ContactBeginEvent e{};
    sensor_event_target(key, e.body, e.other);
    e.user_data = state.bodies.user_data[e.body.index];
    const Vec3 d = state.bodies.position[e.other.body.index] - state.bodies.position[e.body.index];
    e.normal = d.norm() > 0 ? Vec3(d.normalized()) : fallback_normal();
    e.point = state.bodies.position[e.body.index] + e.normal * state.bodies.radius[e.body.index];
    e.approach_speed = 0;
    events.begin_events.push_back(e);
  }
  diff.clear();
  std::set_difference(scratch.previous_sensor_overlaps.begin(),
                      scratch.previous_sensor_overlaps.end(), state.sensor_overlaps.begin(),
                      state.sensor_overlaps.end(), std::back_inserter(diff));
  for (const std::uint64_t key : diff) {
    ContactEndEvent e{};
    sensor_event_target(key, e.body, e.other);
    if (state.bodies.alive(e.body.index) && state.bodies.alive(e.other.body.index)) {
      e.user_data = state.bodies.user_data[e.body.index];
      events.end_events.push_back(e);
    }
  }
}

}  // namespace ricochet::physics
