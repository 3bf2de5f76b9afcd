#pragma once
/// Slots with generation counters and a free list: the one allocator behind bodies, static
/// shapes, projectiles and force fields. A slot's generation is odd while it is in use and even
/// when it is free (0: never used), so a handle is valid exactly when its generation equals the
/// slot's, and a destroyed object's handle goes stale. Freed slots are reused last-in first-out,
/// so the same calls give the same handles (determinism).

#include <cstdint>
#include <string>
#include <vector>

#include "ricochet/physics/types.h"

namespace ricochet::physics {

struct SlotPool {
  std::vector<std::uint32_t> generation;  ///< per slot: odd while alive
  std::vector<std::uint32_t> free_slots;  ///< dead slots, the next to reuse last
  std::uint32_t alive_count = 0;

  std::uint32_t slot_count() const { return static_cast<std::uint32_t>(generation.size()); }
  bool alive(std::uint32_t slot) const { return (generation[slot] & 1u) != 0; }
  template <class Tag>
  bool valid(Handle<Tag> id) const {
    return id.index < slot_count() && (id.generation & 1u) != 0 &&
           generation[id.index] == id.generation;
  }
  template <class Tag>
  Handle<Tag> id_of(std::uint32_t slot) const {
    return {slot, generation[slot]};
  }
  /// Whether acquire() would need a slot beyond max_slots.
  bool full(std::uint32_t max_slots) const {
    return free_slots.empty() && slot_count() >= max_slots;
  }

  /// A dead slot (the last freed) or a new one at the end; the caller grows its arrays to
  /// slot_count().
  std::uint32_t acquire() {
    std::uint32_t slot;
    if (free_slots.empty()) {
      slot = slot_count();
      generation.push_back(0);
    } else {
      slot = free_slots.back();
      free_slots.pop_back();
    }
    ++generation[slot];
    ++alive_count;
    return slot;
  }
  void release(std::uint32_t slot) {
    ++generation[slot];
    free_slots.push_back(slot);
    --alive_count;
  }

  /// After the generations and free list were read from untrusted bytes: every slot on the free
  /// list is dead and listed once, every dead slot is listed; recounts alive_count. Empty when
  /// valid, else what is wrong. `seen` is scratch.
  std::string validate(std::vector<std::uint8_t>& seen) {
    seen.assign(generation.size(), 0);
    for (const std::uint32_t s : free_slots) {
      if (s >= slot_count())
        return "free list names slot " + std::to_string(s) + " of " + std::to_string(slot_count());
      if (alive(s)) return "free list names live slot " + std::to_string(s);
      if (seen[s]++) return "free list names slot " + std::to_string(s) + " twice";
    }
    alive_count = 0;
    for (std::uint32_t s = 0; s < slot_count(); ++s) {
      if (alive(s)) {
        ++alive_count;
      } else if (!seen[s]) {
        return "dead slot " + std::to_string(s) + " missing from the free list";
      }
    }
    return {};
  }
};

}  // namespace ricochet::physics
