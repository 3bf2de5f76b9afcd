/// The shipped scene profiles (see scene_profile.h).

#include "ricochet/physics/scene_profile.h"

namespace ricochet::physics::profiles {

WorldDef arena_players() {
  WorldDef def;
  def.enable_rotation = false;
  def.enable_rolling_resistance = false;
  def.enable_restitution = false;
  def.enable_sleep = false;
  def.iterations = 4;
  return def;
}

WorldDef physics_props() {
  return WorldDef{};
}

BodyDef player(const Vec3& position) {
  BodyDef def;
  def.position = position;
  def.radius = Real(0.4);
  def.mass = 80;
  def.lock_rotation = true;
  def.allow_sleep = false;
  def.material.friction = Real(0.2);
  def.filter = {kLayerPlayer, kLayerStatic | kLayerPlayer | kLayerProjectile | kLayerProp};
  return def;
}

ProjectileDef bullet(const Vec3& position, const Vec3& velocity, BodyId shooter) {
  ProjectileDef def;
  def.position = position;
  def.velocity = velocity;
  def.radius = Real(0.02);
  def.gravity_scale = 0;
  def.filter = {kLayerProjectile, kLayerStatic | kLayerPlayer | kLayerProp};
  def.ignore = shooter;
  return def;
}

BodyDef bullet_body(const Vec3& position, const Vec3& velocity) {
  BodyDef def;
  def.position = position;
  def.linear_velocity = velocity;
  def.radius = Real(0.02);
  def.mass = Real(0.01);
  def.gravity_scale = 0;
  def.lock_rotation = true;
  def.fast = true;
  def.allow_sleep = false;
  def.filter = {kLayerProjectile, kLayerStatic | kLayerPlayer | kLayerProp};
  return def;
}

BodyDef prop(const Vec3& position) {
  BodyDef def;
  def.position = position;
  def.radius = Real(0.5);
  def.mass = 5;
  def.material.restitution = Real(0.3);
  def.material.rolling_resistance = Real(0.02);
  def.filter = {kLayerProp, 0xFFFFFFFFu};
  return def;
}

}  // namespace ricochet::physics::profiles
