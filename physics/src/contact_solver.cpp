/// Sequential impulses over sphere contacts, with integration, per (sub)step:
///
///   prepare → for each substep { integrate velocities → warm start → iterate (biased)
///             → integrate positions → relax (unbiased, SoftStep) } → restitution → store impulses
///
/// Accumulated impulses are clamped (normal >= 0, friction inside the Coulomb circle, rolling
/// inside its torque limit) and carried across steps for warm starting. Position error is removed
/// by the chosen PositionCorrection. Friction is one 2-D impulse in the tangent plane clamped to a
/// circle (isotropic Coulomb), equivalent to two tangent rows without the box-clamp bias.
/// Spheres touch on the line between centres, so the normal impulse has no torque.

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <numbers>
#include <type_traits>

#include "math_util.h"
#include "world_impl.h"

namespace ricochet::physics {

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

constexpr int kColors = 24;
constexpr std::uint32_t kUnusedLane = ~0u;

/// Box2D v3 soft constraint coefficients for a contact spring of `hertz` with damping `zeta`.
struct Softness {
  Real bias_rate = 0;
  Real mass_scale = 1;
  Real impulse_scale = 0;
};

Softness make_softness(Real hertz, Real zeta, Real h) {
  if (hertz <= 0) return {};
  const Real omega = 2 * std::numbers::pi_v<Real> * hertz;
  const Real a1 = 2 * zeta + h * omega;
  const Real a2 = h * omega * a1;
  const Real a3 = 1 / (1 + a2);
  return {omega / a1, a2 * a3, a3};
}

/// Parameters of one pass over the contacts.
struct PassParams {
  Real inverse_h;
  Real slop;
  Real baumgarte;
  Real max_correction_speed;
  Softness soft;
};

inline Lanes splat(Real x) {
  return Lanes{} + x;
}
inline Lanes max_lanes(Lanes a, Lanes b) {
  return a > b ? a : b;
}
inline Lanes min_lanes(Lanes a, Lanes b) {
  return a < b ? a : b;
}

inline Lanes sqrt_lanes(Lanes x) {
  Lanes r;
  for (int l = 0; l < kLanes; ++l) r[l] = std::sqrt(x[l]);
  return r;
}

/// Factor that brings a vector of squared length len2 inside a circle of radius limit (>= 0).
inline Lanes circle_clamp_scale(Lanes len2, Lanes limit) {
  const auto outside = len2 > limit * limit;  // implies len2 > 0
  const Lanes safe_len2 = outside ? len2 : splat(1);
  return outside ? limit / sqrt_lanes(safe_len2) : splat(1);
}

struct BodyLanes {
  Lanes vx, vy, vz, m, wx, wy, wz, i;
};

static_assert(sizeof(Motion) == 2 * sizeof(Lanes), "Motion must be two lane vectors: v|m and w|i");
using LaneIndex = std::conditional_t<sizeof(Real) == 4, std::int32_t, std::int64_t>;
using Shuffle = LaneIndex __attribute__((vector_size(kLanes * sizeof(Real))));

/// 4×4 transpose: rows (x, y, z, s) of four bodies become lanes x, y, z, s.
inline void transpose(Lanes r0, Lanes r1, Lanes r2, Lanes r3, Lanes& x, Lanes& y, Lanes& z,
                      Lanes& s) {
  const Lanes t0 = __builtin_shuffle(r0, r1, Shuffle{0, 4, 1, 5});
  const Lanes t1 = __builtin_shuffle(r2, r3, Shuffle{0, 4, 1, 5});
  const Lanes t2 = __builtin_shuffle(r0, r1, Shuffle{2, 6, 3, 7});
  const Lanes t3 = __builtin_shuffle(r2, r3, Shuffle{2, 6, 3, 7});
  x = __builtin_shuffle(t0, t1, Shuffle{0, 1, 4, 5});
  y = __builtin_shuffle(t0, t1, Shuffle{2, 3, 6, 7});
  z = __builtin_shuffle(t2, t3, Shuffle{0, 1, 4, 5});
  s = __builtin_shuffle(t2, t3, Shuffle{2, 3, 6, 7});
}

inline Lanes load(const Real* p) {
  Lanes v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

inline void store(Real* p, Lanes v) {
  std::memcpy(p, &v, sizeof v);
}

inline BodyLanes gather(const Motion* bodies, const std::uint32_t* index) {
  static_assert(kLanes == 4);
  BodyLanes r;
  const Real* b0 = bodies[index[0]].linear_velocity.data();
  const Real* b1 = bodies[index[1]].linear_velocity.data();
  const Real* b2 = bodies[index[2]].linear_velocity.data();
  const Real* b3 = bodies[index[3]].linear_velocity.data();
  transpose(load(b0), load(b1), load(b2), load(b3), r.vx, r.vy, r.vz, r.m);
  transpose(load(b0 + 4), load(b1 + 4), load(b2 + 4), load(b3 + 4), r.wx, r.wy, r.wz, r.i);
  return r;
}

/// Writes velocities back (the inverse masses ride along unchanged).
inline void scatter(Motion* bodies, const std::uint32_t* index, const BodyLanes& r) {
  Lanes v[4], w[4];
  transpose(r.vx, r.vy, r.vz, r.m, v[0], v[1], v[2], v[3]);
  transpose(r.wx, r.wy, r.wz, r.i, w[0], w[1], w[2], w[3]);
  for (int l = 0; l < kLanes; ++l) {
    Real* b = bodies[index[l]].linear_velocity.data();
    store(b, v[l]);
    store(b + 4, w[l]);
  }
}

/// Normal component of a per-body vector difference (b - a), lane-wise.
inline Lanes normal_difference(const Vec3* v, const ContactBlock& c) {
  Lanes d;
  for (int l = 0; l < kLanes; ++l) {
    const Vec3 diff = v[c.b[l]] - v[c.a[l]];
    d[l] = diff.x() * c.nx[l] + diff.y() * c.ny[l] + diff.z() * c.nz[l];
  }
  return d;
}

/// One pass over every block: rolling, friction, then normal (normal last: it matters most).
/// flatten: GCC otherwise leaves small Eigen operators as calls in this hot loop.
template <PositionCorrection kMethod, bool kUseBias, bool kTrackDelta, bool kRolling>
[[gnu::flatten]] void solve_blocks(SolverScratch& s, const PassParams& p) {
  Motion* sb = s.bodies.data();
  const Vec3* delta = s.delta_position.data();
  Vec3* pseudo = s.pseudo_velocity.data();
  const std::size_t count = s.blocks.size();
  for (std::size_t k = 0; k < count; ++k) {
    ContactBlock& c = s.blocks[k];
    BodyLanes A = gather(sb, c.a);
    BodyLanes B = gather(sb, c.b);

    if constexpr (kRolling) {
      RollingBlock& r = s.rolling[k];
      const Lanes limit = r.limit * c.normal_impulse;
      Lanes x = r.x - r.mass * (B.wx - A.wx);
      Lanes y = r.y - r.mass * (B.wy - A.wy);
      Lanes z = r.z - r.mass * (B.wz - A.wz);
      const Lanes scale = circle_clamp_scale(x * x + y * y + z * z, limit);
      x *= scale, y *= scale, z *= scale;
      const Lanes ix = x - r.x, iy = y - r.y, iz = z - r.z;
      r.x = x, r.y = y, r.z = z;
      A.wx -= A.i * ix, A.wy -= A.i * iy, A.wz -= A.i * iz;
      B.wx += B.i * ix, B.wy += B.i * iy, B.wz += B.i * iz;
    }

    {  // Friction on the relative tangential velocity at the contact point.
      const Lanes sx = c.ra * A.wx + c.rb * B.wx;
      const Lanes sy = c.ra * A.wy + c.rb * B.wy;
      const Lanes sz = c.ra * A.wz + c.rb * B.wz;
      const Lanes dvx = B.vx - A.vx - (sy * c.nz - sz * c.ny);
      const Lanes dvy = B.vy - A.vy - (sz * c.nx - sx * c.nz);
      const Lanes dvz = B.vz - A.vz - (sx * c.ny - sy * c.nx);
      const Lanes dvn = dvx * c.nx + dvy * c.ny + dvz * c.nz;
      Lanes fx = c.fx - c.tangent_mass * (dvx - c.nx * dvn);
      Lanes fy = c.fy - c.tangent_mass * (dvy - c.ny * dvn);
      Lanes fz = c.fz - c.tangent_mass * (dvz - c.nz * dvn);
      const Lanes scale =
          circle_clamp_scale(fx * fx + fy * fy + fz * fz, c.friction * c.normal_impulse);
      fx *= scale, fy *= scale, fz *= scale;
      const Lanes ix = fx - c.fx, iy = fy - c.fy, iz = fz - c.fz;
      c.fx = fx, c.fy = fy, c.fz = fz;
      const Lanes tx = c.ny * iz - c.nz * iy, ty = c.nz * ix - c.nx * iz,
                  tz = c.nx * iy - c.ny * ix;
      const Lanes ka = A.i * c.ra, kb = B.i * c.rb;
      A.vx -= A.m * ix, A.vy -= A.m * iy, A.vz -= A.m * iz;
      A.wx -= ka * tx, A.wy -= ka * ty, A.wz -= ka * tz;
      B.vx += B.m * ix, B.vy += B.m * iy, B.vz += B.m * iz;
      B.wx -= kb * tx, B.wy -= kb * ty, B.wz -= kb * tz;
    }

    {  // Normal.
      Lanes separation = c.separation;
      if constexpr (kTrackDelta) separation += normal_difference(delta, c);
      const auto speculative = separation > 0;
      Lanes bias = separation * p.inverse_h;  // speculative: may close the gap, no further
      Lanes mass_scale = splat(1), impulse_scale = splat(0);
      if constexpr (kUseBias && kMethod == PositionCorrection::Baumgarte) {
        const Lanes correction =
            max_lanes(p.baumgarte * p.inverse_h * min_lanes(separation + p.slop, splat(0)),
                      splat(-p.max_correction_speed));
        bias = speculative ? bias : correction;
      } else if constexpr (kUseBias && kMethod == PositionCorrection::SoftStep) {
        const Lanes correction =
            max_lanes(p.soft.bias_rate * separation, splat(-p.max_correction_speed));
        bias = speculative ? bias : correction;
        mass_scale = speculative ? mass_scale : splat(p.soft.mass_scale);
        impulse_scale = speculative ? impulse_scale : splat(p.soft.impulse_scale);
      } else {
        bias = speculative ? bias : splat(0);
      }
      const Lanes vn = (B.vx - A.vx) * c.nx + (B.vy - A.vy) * c.ny + (B.vz - A.vz) * c.nz;
      const Lanes impulse =
          -c.normal_mass * mass_scale * (vn + bias) - impulse_scale * c.normal_impulse;
      const Lanes accumulated = max_lanes(c.normal_impulse + impulse, splat(0));
      const Lanes applied = accumulated - c.normal_impulse;
      c.normal_impulse = accumulated;
      c.max_normal_impulse = max_lanes(c.max_normal_impulse, accumulated);
      const Lanes pa = A.m * applied, pb = B.m * applied;
      A.vx -= pa * c.nx, A.vy -= pa * c.ny, A.vz -= pa * c.nz;
      B.vx += pb * c.nx, B.vy += pb * c.ny, B.vz += pb * c.nz;

      if constexpr (kMethod == PositionCorrection::SplitImpulse && kUseBias) {
        // Pseudo-velocities push penetrating bodies apart without adding momentum.
        ContactBlockExtra& e = s.extra[k];
        const Lanes target =
            min_lanes(-p.baumgarte * p.inverse_h * min_lanes(separation + p.slop, splat(0)),
                      splat(p.max_correction_speed));
        const Lanes pvn = normal_difference(pseudo, c);
        const Lanes next = max_lanes(e.pseudo_impulse - c.normal_mass * (pvn - target), splat(0));
        const Lanes pseudo_applied = next - e.pseudo_impulse;
        e.pseudo_impulse = next;
        for (int l = 0; l < kLanes; ++l) {
          const Vec3 n(c.nx[l], c.ny[l], c.nz[l]);
          pseudo[c.a[l]] -= (A.m[l] * pseudo_applied[l]) * n;
          pseudo[c.b[l]] += (B.m[l] * pseudo_applied[l]) * n;
        }
      }
    }
    scatter(sb, c.a, A);
    scatter(sb, c.b, B);
  }
}

template <PositionCorrection kMethod, bool kUseBias>
void solve_blocks_dispatch(SolverScratch& s, bool track_delta, const PassParams& p) {
  if (track_delta) {
    if (s.has_rolling) {
      solve_blocks<kMethod, kUseBias, true, true>(s, p);
    } else {
      solve_blocks<kMethod, kUseBias, true, false>(s, p);
    }
  } else if (s.has_rolling) {
    solve_blocks<kMethod, kUseBias, false, true>(s, p);
  } else {
    solve_blocks<kMethod, kUseBias, false, false>(s, p);
  }
}

template <PositionCorrection kMethod>
void solve_blocks_with(SolverScratch& s, bool use_bias, bool track_delta, const PassParams& p) {
  if (use_bias) {
    solve_blocks_dispatch<kMethod, true>(s, track_delta, p);
  } else {
    solve_blocks_dispatch<kMethod, false>(s, track_delta, p);
  }
}

}  // namespace

void WorldImpl::prepare_contacts() {
  SolverScratch& s = solver;
  const std::uint32_t awake = static_cast<std::uint32_t>(awake_list.size());
  const std::uint32_t dummy = awake;
  s.index_of.assign(bodies.slot_count(), dummy);
  s.bodies.resize(awake + 1);
  s.has_rolling = false;
  for (std::uint32_t k = 0; k < awake; ++k) {
    const std::uint32_t slot = awake_list[k];
    s.index_of[slot] = k;
    s.bodies[k] = bodies.motion[slot];
    s.has_rolling = s.has_rolling || bodies.material[slot].rolling_resistance > 0;
  }
  s.bodies[dummy] = Motion{};
  s.delta_position.assign(awake + 1, Vec3::Zero());
  if (def.position_correction == PositionCorrection::SplitImpulse)
    s.pseudo_velocity.assign(awake + 1, Vec3::Zero());

  // Greedy colouring: a contact takes the first colour where neither of its moving bodies is used.
  const std::size_t pair_count = pair_contacts.size();
  const std::size_t total = pair_count + static_contacts.size();
  const auto contact_at = [&](std::size_t i) -> Contact& {
    return i < pair_count ? pair_contacts[i] : static_contacts[i - pair_count];
  };
  // used_colors[k]: bit c set when body k already has a contact of colour c (the dummy never does).
  std::vector<std::uint32_t>& used_colors = s.used_colors;
  used_colors.assign(awake + 1, 0);
  s.color_of.resize(total);
  std::vector<std::uint32_t> color_count(kColors + 1, 0);
  for (std::size_t i = 0; i < total; ++i) {
    const Contact& c = contact_at(i);
    const std::uint32_t a = s.index_of[c.a];
    const std::uint32_t b = i < pair_count ? s.index_of[c.b] : dummy;
    const std::uint32_t free_colors = ~(used_colors[a] | used_colors[b]) & ((1u << kColors) - 1);
    const std::uint32_t color =
        free_colors != 0 ? static_cast<std::uint32_t>(std::countr_zero(free_colors)) : kColors;
    if (color < kColors) {
      if (a != dummy) used_colors[a] |= 1u << color;
      if (b != dummy) used_colors[b] |= 1u << color;
    }
    s.color_of[i] = color;
    ++color_count[color];
  }
  std::size_t block_count = total > 0 ? color_count[kColors] : 0;
  for (int k = 0; k < kColors; ++k) block_count += (color_count[k] + kLanes - 1) / kLanes;
  s.blocks.assign(block_count, ContactBlock{});
  s.extra.assign(block_count, ContactBlockExtra{});
  s.rolling.assign(s.has_rolling ? block_count : 0, RollingBlock{});

  // Block ranges per colour; overflow contacts get a block each.
  std::vector<std::uint32_t> next_block(kColors + 1), next_lane(kColors + 1, 0);
  std::uint32_t first = 0;
  for (int k = 0; k <= kColors; ++k) {
    next_block[k] = first;
    first += k < kColors ? (color_count[k] + kLanes - 1) / kLanes : color_count[k];
  }
  for (std::size_t b = 0; b < block_count; ++b) {
    for (int l = 0; l < kLanes; ++l) {
      s.blocks[b].a[l] = s.blocks[b].b[l] = dummy;
      s.extra[b].contact[l] = kUnusedLane;
    }
  }
  for (std::size_t i = 0; i < total; ++i) {
    Contact& c = contact_at(i);
    const std::uint32_t color = s.color_of[i];
    const std::uint32_t block = next_block[color];
    const int lane = static_cast<int>(next_lane[color]);
    if (color == kColors || lane + 1 == kLanes) {
      ++next_block[color];
      next_lane[color] = 0;
    } else {
      ++next_lane[color];
    }
    ContactBlock& blk = s.blocks[block];
    ContactBlockExtra& extra = s.extra[block];
    const std::uint32_t a = s.index_of[c.a];
    const std::uint32_t b = i < pair_count ? s.index_of[c.b] : dummy;
    const Motion& A = s.bodies[a];
    const Motion& B = s.bodies[b];
    blk.a[lane] = a;
    blk.b[lane] = b;
    blk.nx[lane] = c.normal.x(), blk.ny[lane] = c.normal.y(), blk.nz[lane] = c.normal.z();
    blk.separation[lane] = c.separation;
    blk.ra[lane] = c.ra, blk.rb[lane] = c.rb;
    const Real mass_sum = A.inverse_mass + B.inverse_mass;
    blk.normal_mass[lane] = mass_sum > 0 ? 1 / mass_sum : Real(0);
    const Real tangent_sum =
        mass_sum + A.inverse_inertia * c.ra * c.ra + B.inverse_inertia * c.rb * c.rb;
    blk.tangent_mass[lane] = tangent_sum > 0 ? 1 / tangent_sum : Real(0);
    blk.friction[lane] = c.friction;
    const Vec3 f = c.friction_impulse - c.normal * c.normal.dot(c.friction_impulse);
    blk.normal_impulse[lane] = c.normal_impulse;
    blk.fx[lane] = f.x(), blk.fy[lane] = f.y(), blk.fz[lane] = f.z();
    blk.max_normal_impulse[lane] = 0;
    if (s.has_rolling) {
      RollingBlock& r = s.rolling[block];
      const Real rolling_sum = A.inverse_inertia + B.inverse_inertia;
      r.limit[lane] = c.rolling;
      r.mass[lane] = rolling_sum > 0 ? 1 / rolling_sum : Real(0);
      r.x[lane] = c.rolling_impulse.x(), r.y[lane] = c.rolling_impulse.y(),
      r.z[lane] = c.rolling_impulse.z();
    }
    extra.contact[lane] = static_cast<std::uint32_t>(i);
    extra.relative_velocity[lane] = c.normal.dot(B.linear_velocity - A.linear_velocity);
    extra.restitution[lane] = c.restitution;
  }
}

void WorldImpl::warm_start() {
  SolverScratch& s = solver;
  for (std::size_t k = 0; k < s.blocks.size(); ++k) {
    const ContactBlock& c = s.blocks[k];
    for (int l = 0; l < kLanes; ++l) {
      if (s.extra[k].contact[l] == kUnusedLane) continue;
      const Vec3 n(c.nx[l], c.ny[l], c.nz[l]);
      const Vec3 f(c.fx[l], c.fy[l], c.fz[l]);
      const Vec3 rolling = s.has_rolling
                               ? Vec3(s.rolling[k].x[l], s.rolling[k].y[l], s.rolling[k].z[l])
                               : Vec3::Zero().eval();
      const Vec3 linear = n * c.normal_impulse[l] + f;
      const Vec3 torque_dir = n.cross(f);
      Motion& A = s.bodies[c.a[l]];
      Motion& B = s.bodies[c.b[l]];
      A.linear_velocity -= A.inverse_mass * linear;
      A.angular_velocity -= A.inverse_inertia * (c.ra[l] * torque_dir + rolling);
      B.linear_velocity += B.inverse_mass * linear;
      B.angular_velocity += B.inverse_inertia * (rolling - c.rb[l] * torque_dir);
    }
  }
}

void WorldImpl::reset_impulses() {
  SolverScratch& s = solver;
  for (ContactBlock& c : s.blocks) c.normal_impulse = c.fx = c.fy = c.fz = splat(0);
  for (RollingBlock& r : s.rolling) r.x = r.y = r.z = splat(0);
}

void WorldImpl::solve_contacts(Real h, bool use_bias) {
  PassParams p;
  p.inverse_h = 1 / h;
  p.slop = def.linear_slop;
  p.baumgarte = def.baumgarte;
  p.max_correction_speed = def.max_correction_speed;
  p.soft = make_softness(std::min(def.contact_hertz, Real(0.25) / h), def.contact_damping_ratio, h);
  const bool track_delta = def.substeps > 1;
  SolverScratch& s = solver;
  switch (def.position_correction) {
    case PositionCorrection::Baumgarte:
      solve_blocks_with<PositionCorrection::Baumgarte>(s, use_bias, track_delta, p);
      break;
    case PositionCorrection::SplitImpulse:
      solve_blocks_with<PositionCorrection::SplitImpulse>(s, use_bias, track_delta, p);
      break;
    case PositionCorrection::SoftStep:
      solve_blocks_with<PositionCorrection::SoftStep>(s, use_bias, track_delta, p);
      break;
  }
}

void WorldImpl::apply_restitution() {
  SolverScratch& s = solver;
  const Real threshold = def.restitution_threshold;
  for (std::size_t k = 0; k < s.blocks.size(); ++k) {
    ContactBlock& c = s.blocks[k];
    ContactBlockExtra& e = s.extra[k];
    for (int l = 0; l < kLanes; ++l) {
      if (e.contact[l] == kUnusedLane || e.restitution[l] == 0 ||
          e.relative_velocity[l] > -threshold || c.max_normal_impulse[l] == 0) {
        continue;
      }
      const Vec3 n(c.nx[l], c.ny[l], c.nz[l]);
      Motion& A = s.bodies[c.a[l]];
      Motion& B = s.bodies[c.b[l]];
      const Real vn = n.dot(B.linear_velocity - A.linear_velocity);
      const Real impulse = -c.normal_mass[l] * (vn + e.restitution[l] * e.relative_velocity[l]);
      const Real accumulated = std::max(c.normal_impulse[l] + impulse, Real(0));
      const Real applied = accumulated - c.normal_impulse[l];
      c.normal_impulse[l] = accumulated;
      c.max_normal_impulse[l] = std::max(c.max_normal_impulse[l], accumulated);
      e.total_normal_impulse[l] += applied;
      A.linear_velocity -= (A.inverse_mass * applied) * n;
      B.linear_velocity += (B.inverse_mass * applied) * n;
    }
  }
}

void WorldImpl::store_impulses() {
  SolverScratch& s = solver;
  const std::size_t pair_count = pair_contacts.size();
  for (std::size_t k = 0; k < s.blocks.size(); ++k) {
    const ContactBlock& c = s.blocks[k];
    const ContactBlockExtra& e = s.extra[k];
    for (int l = 0; l < kLanes; ++l) {
      const std::uint32_t i = e.contact[l];
      if (i == kUnusedLane) continue;
      Contact& contact = i < pair_count ? pair_contacts[i] : static_contacts[i - pair_count];
      contact.normal_impulse = c.normal_impulse[l];
      contact.friction_impulse = Vec3(c.fx[l], c.fy[l], c.fz[l]);
      if (s.has_rolling)
        contact.rolling_impulse = Vec3(s.rolling[k].x[l], s.rolling[k].y[l], s.rolling[k].z[l]);
      contact.max_normal_impulse = c.max_normal_impulse[l];
      contact.total_normal_impulse = e.total_normal_impulse[l];
      contact.relative_velocity = e.relative_velocity[l];
    }
  }
  for (std::size_t k = 0; k < awake_list.size(); ++k)
    bodies.motion[awake_list[k]] = solver.bodies[k];
}

void WorldImpl::integrate_velocities(Real h) {
  const Real max_linear2 = def.max_linear_speed * def.max_linear_speed;
  const Real max_angular2 = def.max_angular_speed * def.max_angular_speed;
  for (std::size_t k = 0; k < awake_list.size(); ++k) {
    const std::uint32_t slot = awake_list[k];
    if (!bodies.simulated(slot)) continue;  // kinematic, or frozen this step
    Motion& m = solver.bodies[k];
    m.linear_velocity +=
        h * (def.gravity * bodies.gravity_scale[slot] + bodies.force[slot] * m.inverse_mass);
    m.angular_velocity += (h * m.inverse_inertia) * bodies.torque[slot];
    if (!is_finite(m.linear_velocity) || !is_finite(m.angular_velocity)) {
      freeze_body(slot);  // before any contact can carry the bad value to a neighbour
      m = Motion{};
      continue;
    }
    const Real v2 = m.linear_velocity.squaredNorm();
    if (v2 > max_linear2) m.linear_velocity *= def.max_linear_speed / std::sqrt(v2);
    const Real w2 = m.angular_velocity.squaredNorm();
    if (w2 > max_angular2) m.angular_velocity *= def.max_angular_speed / std::sqrt(w2);
  }
}

void WorldImpl::integrate_positions(Real h) {
  const bool split = def.position_correction == PositionCorrection::SplitImpulse;
  const bool ballistic = def.integrator == Integrator::ExactBallistic;
  for (std::size_t k = 0; k < awake_list.size(); ++k) {
    const std::uint32_t slot = awake_list[k];
    if (bodies.has(slot, kFlagFrozen)) continue;
    const Motion& m = solver.bodies[k];
    Vec3 move = m.linear_velocity * h;
    if (split) {
      move += solver.pseudo_velocity[k] * h;
      solver.pseudo_velocity[k].setZero();
    }
    if (ballistic && contact_count[slot] == 0 && !bodies.has(slot, kFlagKinematic)) {
      // v already includes a·h, so x + v·h - ½a·h² = x + v0·h + ½a·h²: exact for constant a.
      const Vec3 acceleration =
          def.gravity * bodies.gravity_scale[slot] + bodies.force[slot] * m.inverse_mass;
      move -= acceleration * (Real(0.5) * h * h);
    }
    bodies.position[slot] += move;
    solver.delta_position[k] += move;
    const Vec3& w = m.angular_velocity;
    if (w.x() != 0 || w.y() != 0 || w.z() != 0) {
      Quat& q = bodies.orientation[slot];
      const Quat dq = Quat(0, w.x(), w.y(), w.z()) * q;
      const Real half_h = Real(0.5) * h;
      q = Quat(q.w() + half_h * dq.w(), q.x() + half_h * dq.x(), q.y() + half_h * dq.y(),
               q.z() + half_h * dq.z());
      q.normalize();
    }
  }
}

void WorldImpl::solve(Real step_dt) {
  const auto start = Clock::now();
  double integrate_ms = 0;
  const int substeps = def.substeps;
  const Real h = step_dt / static_cast<Real>(substeps);
  const bool explicit_euler = def.integrator == Integrator::ExplicitEuler;
  const bool relax = def.position_correction == PositionCorrection::SoftStep;
  prepare_contacts();
  if (!def.warm_starting) reset_impulses();
  const auto timed = [&](auto&& integrate) {
    const auto t0 = Clock::now();
    integrate();
    integrate_ms += ms_since(t0);
  };
  for (int sub = 0; sub < substeps; ++sub) {
    if (!explicit_euler) timed([&] { integrate_velocities(h); });
    if (def.warm_starting) {
      warm_start();
    } else if (sub > 0) {
      reset_impulses();
    }
    for (int i = 0; i < def.iterations; ++i) solve_contacts(h, true);
    timed([&] { integrate_positions(h); });
    if (relax) {
      for (int i = 0; i < def.relax_iterations; ++i) solve_contacts(h, false);
    }
    if (explicit_euler) timed([&] { integrate_velocities(h); });
    for (std::size_t k = 0; k < solver.blocks.size(); ++k) {
      solver.extra[k].total_normal_impulse += solver.blocks[k].normal_impulse;
    }
  }
  apply_restitution();
  store_impulses();
  profile.integrate_ms = integrate_ms;
  profile.solve_ms = ms_since(start) - integrate_ms;
}

}  // namespace ricochet::physics
