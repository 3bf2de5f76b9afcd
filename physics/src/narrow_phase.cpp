/// Narrowphase: contact point, normal and separation for every candidate, matched against last
/// step's contacts by key so accumulated impulses warm-start the solver.
///
/// Contacts are created while the gap is below the speculative margin (|v|·dt, capped), so the
/// solver can stop a body exactly at the surface instead of letting it sink in first.

#include <algorithm>
#include <bit>
#include <cmath>

#include "scratch_vector.h"
#include "world_impl.h"

namespace ricochet::physics {

void ContactCache::build(const std::vector<Contact>& pairs, const std::vector<Contact>& statics) {
  const std::size_t count = pairs.size() + statics.size();
  std::size_t capacity = 16;
  while (capacity < 2 * count) capacity <<= 1;
  assign_reusing(keys_, capacity, kEmpty);
  values_.resize(capacity);
  mask_ = capacity - 1;
  shift_ = 64 - static_cast<unsigned>(std::countr_zero(capacity));
  const auto insert = [&](std::uint64_t key, std::uint32_t value) {
    std::uint64_t slot = slot_of(key);
    while (keys_[slot] != kEmpty) slot = (slot + 1) & mask_;
    keys_[slot] = key;
    values_[slot] = value;
  };
  for (std::size_t i = 0; i < pairs.size(); ++i)
    insert(pairs[i].key, static_cast<std::uint32_t>(i));
  for (std::size_t i = 0; i < statics.size(); ++i) {
    insert(statics[i].key, static_cast<std::uint32_t>(pairs.size() + i));
  }
}

std::int64_t ContactCache::find(std::uint64_t key) const {
  if (keys_.empty()) return -1;
  std::uint64_t slot = slot_of(key);
  while (keys_[slot] != kEmpty) {
    if (keys_[slot] == key) return values_[slot];
    slot = (slot + 1) & mask_;
  }
  return -1;
}

namespace {

struct Combined {
  Real friction, restitution, rolling_coefficient;
};

Combined combine(const Material& a, const Material& b) {
  return {std::sqrt(a.friction * b.friction), std::max(a.restitution, b.restitution),
          std::sqrt(a.rolling_resistance * b.rolling_resistance)};
}

}  // namespace

/// A sphere over the inside of one triangle is also near that triangle's edges, which neighbouring
/// triangles report as edge contacts with tilted normals ("internal edges"). An edge or vertex
/// contact whose point lies on a triangle of the same mesh that the sphere touches face-on is
/// such a ghost and is dropped, so a ball rolls and a bullet stops on a flat mesh as on a plane.
bool WorldImpl::edge_covered_by_face(const MeshHit& edge) const {
  const std::uint32_t shape = state.statics.primitive(edge.primitive).shape;
  const Real tolerance = Real(1e-5) + Real(1e-6) * edge.feature.point.norm();
  for (const MeshHit& face : scratch.mesh_hits) {
    if (!face.feature.on_face || state.statics.primitive(face.primitive).shape != shape) continue;
    Vec3 a, b, c;
    state.statics.triangle(state.statics.primitive(face.primitive), a, b, c);
    if ((closest_point_on_triangle(edge.feature.point, a, b, c) - edge.feature.point)
            .squaredNorm() <= tolerance * tolerance) {
      return true;
    }
  }
  return false;
}

void WorldImpl::update_contacts() {
  std::swap(scratch.previous_pair_contacts, state.pair_contacts);
  std::swap(scratch.previous_static_contacts, state.static_contacts);
  scratch.cache.build(scratch.previous_pair_contacts, scratch.previous_static_contacts);
  const std::size_t previous_count =
      scratch.previous_pair_contacts.size() + scratch.previous_static_contacts.size();
  assign_reusing(scratch.previous_matched, previous_count, 0);
  state.pair_contacts.clear();
  state.static_contacts.clear();

  const auto match = [&](Contact& c) {
    const std::int64_t found = scratch.cache.find(c.key);
    if (found < 0) return;
    scratch.previous_matched[static_cast<std::size_t>(found)] = 1;
    const std::size_t pair_count = scratch.previous_pair_contacts.size();
    const Contact& old =
        static_cast<std::size_t>(found) < pair_count
            ? scratch.previous_pair_contacts[static_cast<std::size_t>(found)]
            : scratch.previous_static_contacts[static_cast<std::size_t>(found) - pair_count];
    c.previously_touching = old.touching;
    if (def.warm_starting) {
      c.normal_impulse = old.normal_impulse;
      c.friction_impulse = old.friction_impulse;
      c.rolling_impulse = old.rolling_impulse;
    }
  };

  // Body pairs.
  for (const BodyPair& pair : scratch.pairs) {
    const std::uint16_t fa = state.bodies.flags[pair.a], fb = state.bodies.flags[pair.b];
    const bool active_a = (fa & (kFlagSleeping | kFlagFrozen)) == 0;
    const bool active_b = (fb & (kFlagSleeping | kFlagFrozen)) == 0;
    if (!active_a && !active_b) continue;
    const Vec3 d = state.bodies.position[pair.b] - state.bodies.position[pair.a];
    const Real distance = d.norm();
    const Real ra = state.bodies.radius[pair.a], rb = state.bodies.radius[pair.b];
    Contact c;
    c.a = pair.a;
    c.b = pair.b;
    c.key = pair_key(pair.a, pair.b);
    c.normal = distance > Real(1e-9) * (ra + rb) ? Vec3(d / distance) : fallback_normal();
    c.separation = distance - ra - rb;
    c.ra = ra + c.separation / 2;
    c.rb = rb + c.separation / 2;
    c.point = state.bodies.position[pair.a] + c.normal * c.ra;
    const Combined m = combine(state.bodies.material[pair.a], state.bodies.material[pair.b]);
    c.friction = m.friction;
    c.restitution = m.restitution;
    c.rolling = m.rolling_coefficient * (ra * rb / (ra + rb));
    match(c);
    ++scratch.contact_count[pair.a];
    ++scratch.contact_count[pair.b];
    state.pair_contacts.push_back(c);
  }

  // Awake dynamic bodies against static geometry.
  const auto& planes = state.statics.plane_slots();
  for (const std::uint32_t body : scratch.awake_list) {
    if (state.bodies.has(body, kFlagKinematic) || state.bodies.has(body, kFlagSensor)) continue;
    const Vec3& x = state.bodies.position[body];
    const Real r = state.bodies.radius[body];
    const Real margin = scratch.speculative_margin[body];
    const Filter& filter = state.bodies.filter[body];
    const Material& material = state.bodies.material[body];
    const auto add_static = [&](std::uint32_t shape, std::uint32_t triangle, const Vec3& normal_out,
                                Real separation) {
      Contact c;
      c.a = body;
      c.b = shape;
      c.key = static_key(body, shape, triangle);
      c.normal = -normal_out;
      c.separation = separation;
      c.ra = r + separation / 2;
      c.rb = 0;
      c.point = x + c.normal * c.ra;
      const Combined m = combine(material, state.statics.shape(shape).material);
      c.friction = m.friction;
      c.restitution = m.restitution;
      c.rolling = m.rolling_coefficient * r;
      match(c);
      ++scratch.contact_count[body];
      state.static_contacts.push_back(c);
    };
    for (const std::uint32_t slot : planes) {
      const StaticShape& plane = state.statics.shape(slot);
      if (!collides(filter, plane.filter)) continue;
      const Real separation = plane.plane_normal.dot(x) - plane.plane_offset - r;
      if (separation < margin) {
        add_static(slot, 0, plane.plane_normal, separation);
      }
    }
    // Boxes at once; mesh triangles gathered first so edge contacts can be checked against faces.
    scratch.mesh_hits.clear();
    state.statics.query_aabb(Aabb::around_sphere(x, r + margin), [&](std::uint32_t primitive) {
      const StaticPrimitive& p = state.statics.primitive(primitive);
      if (!collides(filter, state.statics.shape(p.shape).filter)) return;
      const ClosestFeature f = state.statics.closest_feature(primitive, x);
      if (f.distance - r >= margin) return;
      if (state.statics.shape(p.shape).type == ShapeType::Mesh) {
        scratch.mesh_hits.push_back({primitive, f});
      } else {
        add_static(p.shape, p.index, f.normal, f.distance - r);
      }
    });
    for (const MeshHit& hit : scratch.mesh_hits) {
      if (!hit.feature.on_face && edge_covered_by_face(hit)) continue;
      const StaticPrimitive& p = state.statics.primitive(hit.primitive);
      add_static(p.shape, p.index, hit.feature.normal, hit.feature.distance - r);
    }
  }
  profile.contacts = static_cast<int>(state.pair_contacts.size() + state.static_contacts.size());
}

}  // namespace ricochet::physics
