/// Force fields: storage and evaluation. Evaluation visits fields in a fixed order (attractors by
/// slot, then the body's springs by slot), so sums are bit-reproducible.

#include "force_fields.h"

#include <algorithm>
#include <cmath>

namespace ricochet::physics {

std::uint32_t ForceFields::add(const ForceField& field) {
  const std::uint32_t slot = slots_.acquire();
  if (fields_.size() < slots_.slot_count()) fields_.resize(slots_.slot_count());
  fields_[slot] = field;
  rebuild_index();
  return slot;
}

void ForceFields::remove(std::uint32_t slot) {
  slots_.release(slot);
  rebuild_index();
}

void ForceFields::remove_springs_of(std::uint32_t body) {
  bool removed = false;
  for (std::uint32_t s = 0; s < fields_.size(); ++s) {
    const ForceField& f = fields_[s];
    if (slots_.alive(s) && f.kind == ForceKind::Spring && f.body == body) {
      slots_.release(s);
      removed = true;
    }
  }
  if (removed) rebuild_index();
}

void ForceFields::assign(SlotPool slots, std::vector<ForceField> fields) {
  slots_ = std::move(slots);
  fields_ = std::move(fields);
  rebuild_index();
}

void ForceFields::rebuild_index() {
  attractors_.clear();
  springs_.clear();
  for (std::uint32_t s = 0; s < fields_.size(); ++s) {
    if (!slots_.alive(s)) continue;
    (fields_[s].kind == ForceKind::Attractor ? attractors_ : springs_).push_back(s);
  }
  std::stable_sort(springs_.begin(), springs_.end(), [&](std::uint32_t a, std::uint32_t b) {
    return fields_[a].body < fields_[b].body;
  });
}

bool ForceFields::acts_on(std::uint32_t body, std::uint32_t layer) const {
  for (const std::uint32_t s : attractors_) {
    if ((layer & fields_[s].mask) != 0) return true;
  }
  const auto first =
      std::lower_bound(springs_.begin(), springs_.end(), body,
                       [&](std::uint32_t s, std::uint32_t b) { return fields_[s].body < b; });
  return first != springs_.end() && fields_[*first].body == body;
}

Vec3 ForceFields::force_on(std::uint32_t body, std::uint32_t layer, Real inverse_mass,
                           const Vec3& x, const Vec3& v) const {
  Vec3 force = Vec3::Zero();
  if (inverse_mass == 0) return force;
  for (const std::uint32_t s : attractors_) {
    const ForceField& f = fields_[s];
    if ((layer & f.mask) == 0) continue;
    const Vec3 d = x - f.point;
    const Real distance = d.norm();
    if (distance == 0) continue;  // at the centre the pull has no direction
    const Real r = std::max(distance, f.min_distance);
    force -= (f.stiffness / (inverse_mass * r * r * distance)) * d;
  }
  const auto first =
      std::lower_bound(springs_.begin(), springs_.end(), body,
                       [&](std::uint32_t s, std::uint32_t b) { return fields_[s].body < b; });
  for (auto it = first; it != springs_.end() && fields_[*it].body == body; ++it) {
    const ForceField& f = fields_[*it];
    const Vec3 d = x - f.point;
    if (f.rest_length == 0) {  // no direction needed: F = -k·d - c·(v·d̂)·d̂
      force -= f.stiffness * d;
      const Real length2 = d.squaredNorm();
      if (f.damping != 0 && length2 > 0) force -= (f.damping * v.dot(d) / length2) * d;
      continue;
    }
    const Real length = d.norm();
    if (length == 0) continue;
    const Vec3 axis = d / length;
    force -= (f.stiffness * (length - f.rest_length) + f.damping * v.dot(axis)) * axis;
  }
  return force;
}

}  // namespace ricochet::physics
