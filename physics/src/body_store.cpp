#include "body_store.h"

namespace ricochet::physics {

namespace {

Real inverse_inertia_of(const BodyDef& def) {
  if (def.type == BodyType::Kinematic || def.lock_rotation) return 0;
  const Real factor = def.inertia == InertiaModel::SolidSphere ? Real(0.4) : Real(2.0 / 3.0);
  return 1 / (factor * def.mass * def.radius * def.radius);
}

template <class T>
void grow_to(std::vector<T>& v, std::uint32_t size) {
  if (v.size() < size) v.resize(size);
}

}  // namespace

std::uint32_t BodyStore::create(const BodyDef& def) {
  const std::uint32_t slot = slots.acquire();
  const std::uint32_t size = slots.slot_count();
  grow_to(flags, size);
  grow_to(position, size);
  grow_to(orientation, size);
  grow_to(motion, size);
  grow_to(force, size);
  grow_to(torque, size);
  grow_to(radius, size);
  grow_to(mass_inverse_original, size);
  grow_to(inertia_inverse_original, size);
  grow_to(gravity_scale, size);
  grow_to(material, size);
  grow_to(filter, size);
  grow_to(sleep_time, size);
  grow_to(user_data, size);

  std::uint16_t f = 0;
  if (def.type == BodyType::Kinematic) f |= kFlagKinematic;
  if (def.lock_rotation) f |= kFlagLockRotation;
  if (def.fast) f |= kFlagFast;
  if (def.sensor) f |= kFlagSensor;
  if (def.allow_sleep) f |= kFlagAllowSleep;
  flags[slot] = f;

  position[slot] = def.position;
  orientation[slot] = def.orientation.normalized();
  const Real inverse_mass = def.type == BodyType::Kinematic ? Real(0) : 1 / def.mass;
  const Real inverse_inertia = inverse_inertia_of(def);
  motion[slot] =
      Motion{def.linear_velocity, inverse_mass,
             def.lock_rotation ? Vec3::Zero().eval() : def.angular_velocity, inverse_inertia};
  mass_inverse_original[slot] = inverse_mass;
  inertia_inverse_original[slot] = inverse_inertia;
  force[slot].setZero();
  torque[slot].setZero();
  radius[slot] = def.radius;
  gravity_scale[slot] = def.gravity_scale;
  material[slot] = def.material;
  filter[slot] = def.filter;
  sleep_time[slot] = 0;
  user_data[slot] = def.user_data;
  return slot;
}

void BodyStore::destroy(std::uint32_t slot) {
  flags[slot] = 0;
  motion[slot] = Motion{};
  slots.release(slot);
}

BodyState BodyStore::state(std::uint32_t slot) const {
  BodyState s;
  s.type = has(slot, kFlagKinematic) ? BodyType::Kinematic : BodyType::Dynamic;
  s.position = position[slot];
  s.orientation = orientation[slot];
  s.linear_velocity = motion[slot].linear_velocity;
  s.angular_velocity = motion[slot].angular_velocity;
  s.force = force[slot];
  s.torque = torque[slot];
  s.radius = radius[slot];
  s.inverse_mass = motion[slot].inverse_mass;
  s.inverse_inertia_world = Mat3::Identity() * motion[slot].inverse_inertia;
  s.sleeping = has(slot, kFlagSleeping);
  s.frozen = has(slot, kFlagFrozen);
  s.user_data = user_data[slot];
  return s;
}

}  // namespace ricochet::physics
