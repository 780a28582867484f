// Which blockers can reach a point: a spatial hash of world-space spheres, each entered in the
// cells its influence ball covers (radius r (1 / min_sin + 1): beyond it the sphere's angular
// radius is under min_sin even after the plane rule of sphere_blocker.h moves it by up to r).
// Rebuilt each frame in O(spheres x cells each covers); never all pairs. Spheres whose ball
// would cover more than kMaxCellsPerSphere cells (or all, when min_sin is 0) go to a list every
// query returns.
//
// Threading: build() on one thread; then candidates() from any number of threads.
#pragma once

#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include <glm/vec3.hpp>

namespace penumbra::blocker_accumulation {

struct WorldSphere {
  glm::vec3 centre{0.0f};
  float radius = 0;
};

class BlockerGrid {
 public:
  static constexpr int kMaxCellsPerSphere = 512;

  struct Candidates {
    std::span<const std::uint32_t> near;        // spheres entered in the point's cell
    std::span<const std::uint32_t> everywhere;  // spheres too large (or too many cells) to bin
  };

  // `spheres` must be finite with radius >= 0 (BlockerAccumulation validates them).
  void build(std::span<const WorldSphere> spheres, float min_sin);
  Candidates candidates(const glm::vec3& p) const;
  float cell_size() const { return cell_; }
  std::size_t binned_entries() const { return entries_; }

 private:
  std::uint64_t key(const glm::vec3& p) const;

  float cell_ = 1;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells_;
  std::vector<std::uint32_t> everywhere_;
  std::size_t entries_ = 0;
};

// Influence radius of a sphere: farther from its centre, its angular radius is below min_sin.
float influence_radius(float radius, float min_sin);

}  // namespace penumbra::blocker_accumulation
