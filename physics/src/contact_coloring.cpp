/// Graph colouring of the step's contacts and their layout in blocks.
///
/// Greedy: each contact, in order (pair contacts, then static contacts), takes the first of
/// kColors colours that neither of its moving bodies has yet, so the contacts of one colour share
/// no moving body and a block of kLanes of them can be solved with one set of vector
/// instructions. The dummy body (statics, kinematic, asleep) never takes a colour. A contact
/// that finds no free colour goes to a block of its own with one live lane.

#include <array>
#include <bit>

#include "contact_solver.h"
#include "scratch_vector.h"

namespace ricochet::physics {

namespace {
constexpr int kColors = 24;
}

void color_contacts(SolverScratch& s, const std::vector<Contact>& pairs,
                    const std::vector<Contact>& statics) {
  const std::uint32_t dummy = static_cast<std::uint32_t>(s.bodies.size() - 1);
  const std::size_t pair_count = pairs.size();
  const std::size_t total = pair_count + statics.size();
  const auto contact_at = [&](std::size_t i) -> const Contact& {
    return i < pair_count ? pairs[i] : statics[i - pair_count];
  };
  // used_colors[k]: bit c set when body k already has a contact of colour c (the dummy never does).
  std::vector<std::uint32_t>& used_colors = s.used_colors;
  assign_reusing(used_colors, dummy + 1, 0);
  s.color_of.resize(total);
  std::array<std::uint32_t, kColors + 1> color_count{};  // the last counts the overflow
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
  assign_reusing(s.blocks, block_count, ContactBlock{});
  assign_reusing(s.extra, block_count, ContactBlockExtra{});
  s.lane_of_contact.resize(total);
  assign_reusing(s.rolling, s.has_rolling ? block_count : 0, RollingBlock{});
  for (std::size_t b = 0; b < block_count; ++b) {
    for (int l = 0; l < kLanes; ++l) {
      s.blocks[b].a[l] = s.blocks[b].b[l] = dummy;
      s.extra[b].contact[l] = kUnusedLane;
    }
  }

  // Block ranges per colour, in colour order; overflow contacts get a block each.
  std::array<std::uint32_t, kColors + 1> next_block{}, next_lane{};
  std::uint32_t first = 0;
  for (int k = 0; k <= kColors; ++k) {
    next_block[k] = first;
    first += k < kColors ? (color_count[k] + kLanes - 1) / kLanes : color_count[k];
  }
  for (std::size_t i = 0; i < total; ++i) {
    const std::uint32_t color = s.color_of[i];
    const std::uint32_t block = next_block[color];
    const std::uint32_t lane = next_lane[color];
    if (color == kColors || lane + 1 == kLanes) {
      ++next_block[color];
      next_lane[color] = 0;
    } else {
      ++next_lane[color];
    }
    s.lane_of_contact[i] = block * kLanes + lane;
  }
}

}  // namespace ricochet::physics
