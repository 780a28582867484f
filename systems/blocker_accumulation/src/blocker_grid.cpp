#include "penumbra/systems/blocker_accumulation/blocker_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace penumbra::blocker_accumulation {
namespace {
std::uint64_t pack(std::int64_t x, std::int64_t y, std::int64_t z) {
  constexpr std::int64_t kBias = std::int64_t{1} << 20;  // 21 bits per axis, wrapping far out
  const auto u = [](std::int64_t v) { return static_cast<std::uint64_t>(v + kBias) & 0x1FFFFFu; };
  return u(x) | (u(y) << 21) | (u(z) << 42);
}
}  // namespace

float influence_radius(float radius, float min_sin) {
  if (!(min_sin > 0)) return std::numeric_limits<float>::infinity();
  return radius * (1 / min_sin + 1);
}

std::uint64_t BlockerGrid::key(const glm::vec3& p) const {
  return pack(static_cast<std::int64_t>(std::floor(p.x / cell_)),
              static_cast<std::int64_t>(std::floor(p.y / cell_)),
              static_cast<std::int64_t>(std::floor(p.z / cell_)));
}

void BlockerGrid::build(std::span<const WorldSphere> spheres, float min_sin) {
  cells_.clear();
  everywhere_.clear();
  entries_ = 0;
  // Cell size: the median influence diameter, so a typical sphere covers at most 2^3 cells.
  std::vector<float> reach;
  reach.reserve(spheres.size());
  for (const WorldSphere& s : spheres)
    if (s.radius > 0) reach.push_back(influence_radius(s.radius, min_sin));
  if (reach.empty()) return;
  std::nth_element(reach.begin(), reach.begin() + reach.size() / 2, reach.end());
  const float median = reach[reach.size() / 2];
  if (!std::isfinite(median)) {
    for (std::uint32_t i = 0; i < spheres.size(); ++i)
      if (spheres[i].radius > 0) everywhere_.push_back(i);
    return;
  }
  cell_ = std::max(2 * median, 1e-3f);
  for (std::uint32_t i = 0; i < spheres.size(); ++i) {
    const WorldSphere& s = spheres[i];
    if (!(s.radius > 0)) continue;
    const float r = influence_radius(s.radius, min_sin);
    const glm::vec3 lo = (s.centre - r) / cell_, hi = (s.centre + r) / cell_;
    const double span = (std::floor(hi.x) - std::floor(lo.x) + 1) *
                        (std::floor(hi.y) - std::floor(lo.y) + 1) *
                        (std::floor(hi.z) - std::floor(lo.z) + 1);
    if (!(span <= kMaxCellsPerSphere)) {
      everywhere_.push_back(i);
      continue;
    }
    for (auto z = static_cast<std::int64_t>(std::floor(lo.z)); z <= std::floor(hi.z); ++z)
      for (auto y = static_cast<std::int64_t>(std::floor(lo.y)); y <= std::floor(hi.y); ++y)
        for (auto x = static_cast<std::int64_t>(std::floor(lo.x)); x <= std::floor(hi.x); ++x) {
          cells_[pack(x, y, z)].push_back(i);
          ++entries_;
        }
  }
}

BlockerGrid::Candidates BlockerGrid::candidates(const glm::vec3& p) const {
  Candidates c;
  c.everywhere = everywhere_;
  if (cells_.empty()) return c;
  const auto it = cells_.find(key(p));
  if (it != cells_.end()) c.near = it->second;
  return c;
}

}  // namespace penumbra::blocker_accumulation
