#pragma once
/// The physics world: create bodies and static shapes, step it, read state, query it, save it.
///
/// One thread owns a World. Create and destroy bodies between steps. Every input is validated:
/// a bad definition or a NaN force returns an Error and changes nothing.

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "ricochet/physics/body.h"
#include "ricochet/physics/events.h"
#include "ricochet/physics/force_field.h"
#include "ricochet/physics/profile.h"
#include "ricochet/physics/projectile.h"
#include "ricochet/physics/query.h"
#include "ricochet/physics/shapes.h"
#include "ricochet/physics/world_def.h"

namespace ricochet::physics {

class WorldImpl;

/// What save_state writes.
enum class StateParts : std::uint8_t {
  /// Self-contained: the configuration (every body's definition, static shapes, force fields)
  /// and the dynamic state. Restores into any world created with the same WorldDef limits.
  All,
  /// Only what steps change (about 60 bytes per moving body in float) and the configuration's
  /// fingerprint; restores in place, cheaply, into a world whose configuration is the same.
  Dynamic,
};

/// Where World::read_bodies writes, one element per id. A span left empty is not read; a
/// non-empty one must hold exactly as many elements as there are ids.
struct BodyReadout {
  std::span<Vec3> positions = {};           ///< m, centre
  std::span<Quat> orientations = {};        ///< unit
  std::span<Vec3> linear_velocities = {};   ///< m/s
  std::span<Vec3> angular_velocities = {};  ///< rad/s
  std::span<std::uint64_t> user_data = {};  ///< BodyDef::user_data
};

class World {
 public:
  /// Fails with InvalidArgument and the first wrong field when def.validate() is not empty.
  static Result<World> create(const WorldDef& def = {});

  World(World&&) noexcept;
  World& operator=(World&&) noexcept;
  ~World();

  // --- bodies ---
  Result<BodyId> create_body(const BodyDef& def);
  Status destroy_body(BodyId id);
  bool is_valid(BodyId id) const;
  Result<BodyState> body_state(BodyId id) const;
  std::uint32_t body_count() const;

  Status set_transform(BodyId id, const Vec3& position, const Quat& orientation);
  Status set_linear_velocity(BodyId id, const Vec3& velocity);
  Status set_angular_velocity(BodyId id, const Vec3& velocity);
  /// N, at the centre of mass, for the next step only.
  Status apply_force(BodyId id, const Vec3& force);
  /// N·m, for the next step only.
  Status apply_torque(BodyId id, const Vec3& torque);
  /// N·s at a world point; changes velocity immediately.
  Status apply_impulse(BodyId id, const Vec3& impulse, const Vec3& point);
  Status wake(BodyId id);

  // --- projectiles (swept, never in contacts; see projectile.h) ---
  Result<ProjectileId> create_projectile(const ProjectileDef& def);
  Status destroy_projectile(ProjectileId id);
  bool is_valid(ProjectileId id) const;
  Result<ProjectileState> projectile_state(ProjectileId id) const;
  std::uint32_t projectile_count() const;

  // --- static geometry ---
  Result<ShapeId> add_plane(const PlaneDef& def);
  Result<ShapeId> add_box(const BoxDef& def);
  Result<ShapeId> add_mesh(const MeshDef& def);
  Status remove_shape(ShapeId id);
  std::uint32_t shape_count() const;

  // --- force fields (evaluated by the integrator; see force_field.h) ---
  Result<ForceId> add_spring(const SpringDef& def);
  Result<ForceId> add_attractor(const AttractorDef& def);
  Status remove_force(ForceId id);
  std::uint32_t force_count() const;

  // --- simulation ---
  /// Advances by dt_s seconds (finite, 0 < dt_s <= 1). Fails with InvalidArgument otherwise.
  Status step(Real dt_s);
  const StepProfile& profile() const;
  const WorldDef& definition() const;
  /// Wakes every body. Fails with InvalidArgument when not finite.
  Status set_gravity(const Vec3& gravity);
  std::uint64_t step_count() const;

  // --- events of the last step ---
  std::span<const ContactBeginEvent> contact_begin_events() const;
  std::span<const ContactEndEvent> contact_end_events() const;
  std::span<const ContactImpulseEvent> contact_impulse_events() const;
  std::span<const NonFiniteEvent> nonfinite_events() const;
  /// Projectiles that hit something this step (and are gone), in projectile slot order.
  std::span<const ProjectileHitEvent> projectile_hit_events() const;

  // --- queries (between steps) ---
  /// Closest hit within max_distance metres of origin along direction (normalised here, so it
  /// need not be unit). A ray starting inside an object does not report that object.
  bool ray_cast_closest(const Vec3& origin, const Vec3& direction, Real max_distance,
                        const QueryFilter& filter, RayHit& hit) const;
  /// All hits along the ray, sorted by distance.
  std::vector<RayHit> ray_cast_all(const Vec3& origin, const Vec3& direction, Real max_distance,
                                   const QueryFilter& filter) const;
  /// First contact of a sphere of radius moved from origin along direction for max_distance.
  bool sphere_cast(const Vec3& origin, Real radius, const Vec3& direction, Real max_distance,
                   const QueryFilter& filter, RayHit& hit) const;
  /// Everything a sphere at center overlaps.
  std::vector<ContactTarget> overlap_sphere(const Vec3& center, Real radius,
                                            const QueryFilter& filter) const;

  // --- what a server reads each tick (body_reads.cpp, queries.cpp) ---
  /// Writes the live bodies' ids to out in slot order, as many as fit, and returns how many bodies
  /// are live (body_count()): a span of that size gets them all.
  std::uint32_t live_bodies(std::span<BodyId> out) const;
  /// Reads the state of many bodies in one call: element i of each non-empty span of out gets
  /// body ids[i]. Fails with InvalidArgument when a non-empty span's size differs from
  /// ids.size(), and with InvalidHandle naming the first null or stale id; on failure nothing is
  /// written.
  Status read_bodies(std::span<const BodyId> ids, const BodyReadout& out) const;
  /// Bodies that moved, woke or fell asleep in the last step (BodyMoveEvent), in slot order.
  std::span<const BodyMoveEvent> body_move_events() const;
  /// Lag compensation: ray_cast_closest against what filter selects in the world (set
  /// filter.bodies = false to leave the live bodies out) plus the caller's spheres, e.g. the
  /// players where the shooter saw them. No body is moved or woken, state_hash() is unchanged. A
  /// proxy whose body is filter.ignore is skipped; on a tie the world's object wins.
  bool ray_cast_spheres(const Vec3& origin, const Vec3& direction, Real max_distance,
                        const QueryFilter& filter, std::span<const SphereProxy> spheres,
                        RayHit& hit) const;
  /// As ray_cast_spheres, for a sphere of radius m swept along the ray (sphere_cast).
  bool sphere_cast_spheres(const Vec3& origin, Real radius, const Vec3& direction,
                           Real max_distance, const QueryFilter& filter,
                           std::span<const SphereProxy> spheres, RayHit& hit) const;

  // --- determinism and rollback ---
  /// 64-bit FNV-1a of the StateParts::Dynamic image: the dynamic state and the configuration's
  /// fingerprint, so it covers everything that is saved.
  std::uint64_t state_hash() const;
  /// Writes the state into `image`, resized to fit; its capacity is reused, so a save per tick
  /// allocates nothing once warm.
  void save_state(std::vector<std::uint8_t>& image, StateParts parts = StateParts::All) const;
  /// The StateParts::All image in a new buffer.
  std::vector<std::uint8_t> save_state() const;
  /// Restores a save_state() image bit-exactly. When the image's configuration is this world's
  /// (by fingerprint) only the dynamic state is read, in place; otherwise the image must hold
  /// its configuration. Validates every length and field and names the first wrong one; on
  /// error the world is unchanged.
  Status restore_state(std::span<const std::uint8_t> bytes);

 private:
  explicit World(std::unique_ptr<WorldImpl> impl);
  std::unique_ptr<WorldImpl> impl_;
};

}  // namespace ricochet::physics
