#pragma once
/// The world's private state and the phases of a step. Each phase lives in its own source file:
///   broad_phase.cpp    find_pairs
///   island_sleep.cpp   wake_touching_islands, update_sleep
///   narrow_phase.cpp   update_contacts
///   contact_solver.cpp solve (prepare, warm start, iterate, integrate, relax, restitution)
///   continuous.cpp     solve_continuous
///   queries.cpp        ray and sphere casts, overlaps (through query_grid.h)
///   body_reads.cpp     live_bodies, read_bodies, body move events
///   state_io.cpp       state_hash, save_state, restore_state
///   events.cpp         report_events
///
/// What a step reads and writes is split three ways, as Box2D v3 keeps b2World apart from its
/// b2StepContext: `WorldState` is everything that is saved, restored and hashed (nothing else
/// is); `StepScratch` is rebuilt or reused each step and never saved; `StepEvents` is what the
/// last step reports.

#include <cstdint>
#include <vector>

#include "body_grid.h"
#include "body_store.h"
#include "contact.h"
#include "contact_solver.h"
#include "force_fields.h"
#include "profile_timer.h"
#include "projectile_store.h"
#include "query_grid.h"
#include "ricochet/physics/world.h"
#include "static_geometry.h"

namespace ricochet::physics {

/// A mesh triangle near a body, before internal-edge filtering.
struct MeshHit {
  std::uint32_t primitive;
  ClosestFeature feature;
};

/// Candidate body pair from the broadphase (a < b by slot).
struct BodyPair {
  std::uint32_t a;
  std::uint32_t b;
};

/// Everything save_state writes, restore_state reads and state_hash covers. A field that is not
/// here is not part of the simulation's state and must be rebuilt by the next step.
struct WorldState {
  BodyStore bodies;
  StaticGeometry statics;
  ForceFields forces;
  ProjectileStore projectiles;
  std::uint64_t steps = 0;
  Vec3 gravity = Vec3::Zero();  ///< m/s², WorldDef::gravity until set_gravity changes it
  /// Contacts of the last step: warm-start impulses and touching state for the next one.
  std::vector<Contact> pair_contacts, static_contacts;
  std::vector<std::uint64_t> sensor_overlaps;  ///< sorted pair keys overlapping after the last step
};

/// Buffers a step fills and reads; sized to the slot count and reused, never saved.
struct StepScratch {
  Real dt = 0;                       ///< s, of the current step
  std::vector<Vec3> start_position;  ///< position at step start (CCD, non-finite restore)
  std::vector<Quat> start_orientation;
  std::vector<Real> speculative_margin;      ///< m, per body this step
  std::vector<std::uint32_t> contact_count;  ///< contacts per body this step (ExactBallistic)
  std::vector<std::uint32_t> awake_list;     ///< simulated body slots this step, ascending
  std::vector<std::uint32_t> nonfinite_slots;
  SolverScratch solver;
  BodyGrid grid;
  std::vector<BodyPair> pairs;
  std::vector<BodyPair> sensor_pairs;
  std::vector<MeshHit> mesh_hits;  ///< narrowphase scratch, one body at a time

  // Last step's contacts while this step's are built (warm starting, begin/end events).
  std::vector<Contact> previous_pair_contacts, previous_static_contacts;
  std::vector<std::uint64_t> previous_sensor_overlaps;  ///< sorted, last step
  std::vector<std::uint8_t> previous_matched;
  std::vector<std::uint64_t> sensor_difference;  ///< event reporting: keys that began or ended
  ContactCache cache;

  // Continuous collision.
  struct SweptBox {
    Vec3 lo, hi;  ///< m, box around a body's whole move this step
    std::uint32_t body;
  };
  static constexpr std::uint32_t kNotFast = 0xFFFFFFFFu;
  std::vector<std::uint32_t> fast_bodies;
  std::vector<std::uint8_t> fast_sweeping;  ///< per fast body: moved far enough to be swept
  std::vector<std::uint32_t> fast_index;    ///< per slot: index into fast_bodies, or kNotFast
  std::vector<SweptBox> swept_boxes;
  std::vector<Real> time_of_impact;

  // Islands (union-find over touching body pairs), used for sleeping.
  std::vector<std::uint32_t> island_parent;
  std::vector<std::uint8_t> island_scratch;  ///< per root: holds an awake body
  std::vector<Real> island_sleep_time;       ///< per root: least sleep time of its bodies

  /// A projectile's move this step and its earliest hit so far (projectiles.cpp).
  struct ProjectileSweep {
    std::uint32_t slot = 0;
    Vec3 from, move;  ///< m
    SweepHit hit;     ///< t = 1: nothing hit
    ContactTarget target;
  };
  std::vector<ProjectileSweep> projectile_sweeps;
};

/// restore_state reads an image into these first and swaps them in only when all of it is valid,
/// so a bad image changes nothing; kept between restores so a rewind per tick allocates nothing.
struct RestoreScratch {
  std::uint64_t steps = 0;
  Vec3 gravity = Vec3::Zero();
  std::vector<std::uint16_t> flags;
  std::vector<Vec3> position;
  std::vector<Quat> orientation;
  std::vector<Motion> motion;
  std::vector<Vec3> force, torque;
  std::vector<Real> sleep_time;
  std::vector<Contact> pair_contacts, static_contacts;
  std::vector<std::uint64_t> sensor_overlaps;
  ProjectileStore projectiles;
  std::vector<std::uint8_t> seen;  ///< slot pool validation
};

/// What the last step reports to game code.
struct StepEvents {
  std::vector<ProjectileHitEvent> projectile_hits;
  std::vector<ContactBeginEvent> begin_events;
  std::vector<ContactEndEvent> end_events;
  std::vector<ContactImpulseEvent> impulse_events;
  std::vector<NonFiniteEvent> nonfinite_events;
  std::vector<ContactEndEvent> pending_end_events;  ///< from destroy/remove between steps
  std::vector<BodyMoveEvent> body_moves;
  /// Per slot: why the next step must report the body (kMoveMark*), whether or not it moves.
  std::vector<std::uint8_t> move_marks;
  std::vector<std::uint32_t> marked_slots;  ///< slots with a move mark set

  void clear_step() {
    begin_events.clear();
    end_events.clear();
    impulse_events.clear();
    nonfinite_events.clear();
    projectile_hits.clear();
    body_moves.clear();
  }
};

class WorldImpl {
 public:
  explicit WorldImpl(const WorldDef& def) : def(def) { state.gravity = def.gravity; }

  Status step(Real dt);

  // --- step phases, in order ---
  void begin_step(Real dt);
  void find_pairs();
  void wake_touching_islands();
  void gather_awake_bodies();
  void update_contacts();
  void solve(Real dt, ProfileTimer& timer);
  void solve_continuous();
  void sweep_bodies_against_bodies();
  /// Fills swept_boxes with a box around every live, non-sensor body's whole move this step,
  /// sorted along x by start then slot (a deterministic order); returns the widest x extent, m.
  Real sort_body_move_boxes();
  void step_projectiles();
  void sweep_projectiles_against_statics();
  void sweep_projectiles_against_bodies();
  void freeze_nonfinite();
  void update_sleep(Real dt);
  void report_events();
  void end_step();

  // --- state images (state_io.cpp) ---
  void save(std::vector<std::uint8_t>& image, StateParts parts) const;
  Status restore(std::span<const std::uint8_t> bytes);
  /// FNV-1a of the configuration section, recomputed only after the configuration changed.
  std::uint64_t config_fingerprint() const;
  /// Called by every API edit of bodies, shapes or force fields (not by steps).
  void configuration_changed() { ++config_version; }
  ShapeId add_shape(StaticShape shape);

  // --- helpers used across phases ---
  bool collides(const Filter& a, const Filter& b) const {
    return (a.layer & b.mask) != 0 && (b.layer & a.mask) != 0;
  }
  void wake_body(std::uint32_t slot);
  void wake_all();
  void freeze_body(std::uint32_t slot);
  void remove_contacts_of(std::uint32_t slot);
  bool edge_covered_by_face(const MeshHit& edge) const;

  // --- solver pieces (contact_solver.cpp) ---
  void prepare_bodies();
  void prepare_contacts();
  // --- integration (integrator.cpp) ---
  /// True when the integrator moves this body exactly for constant acceleration this step.
  bool moves_exactly(std::uint32_t slot) const;
  /// Puts each stored velocity in the form this step's move expects (kFlagExactVelocity).
  void convert_velocity_forms(Real h);
  /// A velocity set by the caller is the velocity at this instant.
  void mark_velocity_as_given(std::uint32_t slot);
  /// m/s² on awake body k (slot) at position x and velocity v: gravity, applied force, fields.
  Vec3 acceleration_of(std::uint32_t slot, const Motion& m, const Vec3& x, const Vec3& v) const;
  /// Semi-implicit Euler, ExactBallistic and Rk4: v += a(x, v)·h (Rk4: a whole free-flight step).
  void integrate_velocities(Real h);
  /// Explicit Euler: a(x, v) at the substep start, applied after the positions moved.
  void evaluate_accelerations();
  void apply_accelerations(Real h);
  void integrate_positions(Real h);
  void clamp_or_freeze(std::uint32_t slot, Motion& m);
  void warm_start();
  void solve_contacts(Real h, bool use_bias);
  void apply_restitution(Real h);
  // --- shock propagation (shock_propagation.cpp) ---
  void order_contacts_by_support();
  void propagate_shock(Real inverse_h, bool use_bias);
  void reset_impulses();
  void store_impulses();

  // --- what a server reads between steps (queries.cpp, body_reads.cpp) ---
  ContactTarget body_target(std::uint32_t slot) const {
    return {state.bodies.id_of(slot), {}, state.bodies.user_data[slot]};
  }
  ContactTarget shape_target(std::uint32_t slot) const {
    return {{}, state.statics.id_of(slot), 0};
  }
  static constexpr std::uint8_t kMoveMarkMoved = 1;    ///< set_transform or create_body
  static constexpr std::uint8_t kMoveMarkWoke = 2;     ///< woken from sleep
  static constexpr std::uint8_t kMoveMarkCreated = 4;  ///< create_body: marked Moved only
  /// A body was moved, created or woken outside the integrator: the next step reports it.
  void mark_for_move_event(std::uint32_t slot, std::uint8_t why);
  /// Fills events.body_moves from the awake bodies after the step, then clears the marks.
  void report_body_moves();
  /// Rebuilt lazily by the first query after a step or a body's move, creation or destruction.
  mutable QueryGrid query_grid;
  mutable std::vector<std::uint32_t> query_stamp;  ///< per slot: last query that tested it
  mutable std::uint32_t query_counter = 0;

  WorldDef def;  ///< as created; def.gravity follows state.gravity
  WorldState state;
  StepScratch scratch;
  StepEvents events;
  StepProfile profile;

  // State images: the configuration's fingerprint cache and reused buffers.
  std::uint64_t config_version = 0;
  mutable std::uint64_t fingerprint = 0;
  mutable std::uint64_t fingerprint_version = ~0ull;
  mutable std::vector<std::uint8_t> image_scratch;       ///< configuration section, for hashing
  mutable std::vector<std::uint8_t> image_scratch_hash;  ///< dynamic image, for state_hash
  RestoreScratch restore_scratch;
};

}  // namespace ricochet::physics
