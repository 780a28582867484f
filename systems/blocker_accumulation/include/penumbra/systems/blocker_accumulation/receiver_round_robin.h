// Which receiving entities a system re-shades this frame within a budget of points: every new
// one (never shaded), then whole entities round robin from `cursor` while the budget lasts (0:
// all; at least one a frame). Shared by blockers.shade and spherical_lights.gather.
// `is_new(item)` says an item was never shaded; `points(item)` is its point count.
// Threading: pure apart from advancing `cursor`.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace penumbra::blocker_accumulation {

template <class Item, class IsNew, class Points>
std::vector<Item> pick_receivers(const std::vector<Item>& all, std::size_t budget,
                                 std::uint64_t& cursor, IsNew&& is_new, Points&& points) {
  std::vector<Item> now;
  std::size_t used = 0;
  for (const Item& it : all) {
    if (is_new(it)) now.push_back(it), used += points(it);
  }
  const std::uint64_t start = cursor;  // the walk's start: cursor itself advances per pick
  for (std::size_t k = 0; k < all.size() && (budget == 0 || used < budget || now.empty()); ++k) {
    const Item& it = all[(start + k) % all.size()];
    if (is_new(it)) continue;
    now.push_back(it);
    used += points(it);
    ++cursor;
  }
  return now;
}

}  // namespace penumbra::blocker_accumulation
