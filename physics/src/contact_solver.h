#pragma once
/// Solver-side data: compact per-step body velocities and graph-coloured contact blocks.
///
/// Contacts are greedily coloured so no two contacts of one colour share a moving body; each
/// colour is cut into blocks of kLanes contacts stored lane-wise (AoSoA), and a block is solved
/// with one set of vector instructions. Contacts that fit no colour get blocks of their own with
/// one live lane. Unused lanes point at the dummy body (index = body count): zero velocity and
/// zero inverse mass, so they change nothing.

#include <cstdint>
#include <vector>

#include "body_store.h"
#include "contact.h"

namespace ricochet::physics {

/// Contacts solved together: one 32-byte vector of Reals, 8 floats or 4 doubles.
constexpr int kLanes = 32 / static_cast<int>(sizeof(Real));
/// kLanes Reals as one vector (GCC/Clang vector extension): one AVX register on the wide path,
/// two SSE2 (or NEON) registers on the baseline path. Aligned to 32 explicitly: the baseline
/// ABI would align it to 16 only, and the AVX2 path reads it with aligned loads.
using Lanes = Real __attribute__((vector_size(kLanes * sizeof(Real)), aligned(32)));
/// ContactBlockExtra::contact of a lane that holds no contact.
constexpr std::uint32_t kUnusedLane = ~0u;

/// Hot contact data for kLanes contacts.
struct ContactBlock {
  std::uint32_t a[kLanes];  ///< solver body index
  std::uint32_t b[kLanes];  ///< solver body index, the dummy for static contacts
  Lanes nx, ny, nz;         ///< normal, a → b
  Lanes separation;         ///< m at step start
  Lanes ra, rb;             ///< m, lever lengths along the normal
  Lanes normal_mass, tangent_mass, friction;
  Lanes normal_impulse;      ///< N·s, accumulated
  Lanes fx, fy, fz;          ///< N·s, friction impulse
  Lanes max_normal_impulse;  ///< N·s
};

/// Rolling resistance data for the same kLanes contacts (used only when some body has it).
struct RollingBlock {
  Lanes limit;    ///< m: torque limit per unit normal impulse
  Lanes mass;     ///< kg·m²
  Lanes x, y, z;  ///< N·m·s, accumulated
};

/// Cold per-block data: restitution, impulse totals, the way back to the Contact.
struct ContactBlockExtra {
  std::uint32_t contact[kLanes];  ///< index into pair contacts, then static contacts; ~0 if unused
  Lanes relative_velocity;        ///< m/s, normal, at prepare
  Lanes restitution;
  Lanes total_normal_impulse;
  Lanes pseudo_impulse;  ///< split impulse
};

/// What a contact does, chosen per world from its features; each is its own solver kernel.
enum class ContactModel : std::uint8_t {
  Normal,       ///< friction off: a push along the normal (no torque on spheres)
  Friction,     ///< rotation off: normal and linear Coulomb friction
  Spin,         ///< normal, friction with its torque
  SpinRolling,  ///< and rolling resistance (some body has it)
};

/// The collision pass's working set (restitution.cpp), filled only in steps with a fast
/// approach: a compact copy of the step's touched contacts (max normal impulse != 0) in lane
/// order, split in what every visit reads (Touched: bodies and normal, 20 bytes in float) and
/// the rest with the pass's state (TouchedState), plus a flag byte per contact for the walks
/// around a body, which read nothing else.
struct RestitutionScratch {
  struct Touched {
    std::uint32_t a, b;  ///< solver bodies
    Vec3 normal;
  };
  struct TouchedState {
    std::uint32_t where;     ///< block · kLanes + lane
    Real separation;         ///< m at step start
    Real normal_mass;        ///< kg
    Real relative_velocity;  ///< m/s, normal, at prepare
    Real restitution;
    Real total_normal_impulse;  ///< N·s, of the solve
    Real collision;             ///< N·s, summed collision impulse; < 0: did not collide
    Real target;                ///< m/s, relative normal velocity the clean-up keeps (once kTaken)
    Real lower;                 ///< N·s, least impulse the clean-up may add (once taken)
    Real applied;               ///< N·s, added by the pass
  };
  enum Flag : std::uint8_t {
    kBounces = 1,  ///< e > 0 and touched
    kFast = 2,     ///< bounces and approached faster than the threshold at step start
    kQueued = 4,
    kCollided = 8,
    kTaken = 16,    ///< has a target that is not NaN
    kCleaned = 32,  ///< queued for the clean-up
  };
  std::vector<Touched> touched;  ///< the first touched_count are this step's
  std::vector<TouchedState> state;
  std::vector<std::uint8_t> flags;
  std::uint32_t touched_count = 0;
  /// Per solver body k, its touched contacts are adjacent[start[k] .. start[k + 1]), each as
  /// index · 2 + side (0: the body is a, 1: b), in lane order.
  std::vector<std::uint32_t> start, adjacent;
  std::vector<Vec3> velocity;               ///< m/s, per solver body: its collision velocity
  std::vector<std::uint8_t> targets_taken;  ///< per solver body: all its contacts have targets
  std::vector<std::uint32_t> queue;         ///< indices into touched
  std::vector<std::uint64_t> collided;      ///< bit per touched contact: it collided
};

struct SolverScratch {
  std::vector<Motion> bodies;             ///< awake bodies in awake_list order, then the dummy
  std::vector<std::uint32_t> index_of;    ///< per slot: solver body index (dummy if not awake)
  std::vector<Vec3> delta_position;       ///< per solver body, m moved this step
  std::vector<Vec3> pseudo_velocity;      ///< per solver body, split impulse
  std::vector<Vec3> acceleration;         ///< per solver body, m/s² applied this substep
  std::vector<Vec3> free_flight_move;     ///< per solver body, m: Rk4 displacement this substep
  std::vector<std::uint8_t> free_flight;  ///< per solver body: moved by Rk4 this substep
  std::vector<ContactBlock> blocks;
  std::vector<RollingBlock> rolling;
  std::vector<ContactBlockExtra> extra;
  // Colouring (contact_coloring.cpp).
  std::vector<std::uint32_t> used_colors;      ///< per solver body: colours it already has
  std::vector<std::uint32_t> color_of;         ///< per contact
  std::vector<std::uint32_t> lane_of_contact;  ///< per contact: block · kLanes + lane
  // Shock propagation (shock_propagation.cpp).
  std::vector<std::uint32_t> adjacency_start, adjacency, cursor;
  std::vector<std::uint32_t> support_level;  ///< per solver body; the dummy (statics) is 0
  std::vector<std::uint32_t> support_key;    ///< per contact: level of its supporting side
  std::vector<std::uint32_t> support_order;  ///< supported contacts, ground up
  RestitutionScratch restitution;
  ContactModel model = ContactModel::Spin;
  bool has_rolling = false;  ///< model == SpinRolling
  bool needs_shock = false;  ///< some contact joins masses more than shock_mass_ratio apart
  bool wide = false;         ///< solve with AVX2 instructions (bit-identical to the baseline path)
};

/// Colours the contacts (pair contacts, then static contacts, indexed in that order) and lays
/// them out: sizes blocks, extra and rolling, points every lane at the dummy body and marks it
/// unused, and fills color_of and lane_of_contact. Reads bodies (for the dummy), index_of and
/// has_rolling, which prepare_bodies has set.
void color_contacts(SolverScratch& s, const std::vector<Contact>& pairs,
                    const std::vector<Contact>& statics);

}  // namespace ricochet::physics
