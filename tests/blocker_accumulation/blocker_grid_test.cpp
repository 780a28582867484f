#include "penumbra/systems/blocker_accumulation/blocker_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include <glm/geometric.hpp>
#include "common/stability.h"

namespace penumbra::blocker_accumulation {
namespace {

std::set<std::uint32_t> all_candidates(const BlockerGrid& g, const glm::vec3& p) {
  const BlockerGrid::Candidates c = g.candidates(p);
  std::set<std::uint32_t> out(c.near.begin(), c.near.end());
  out.insert(c.everywhere.begin(), c.everywhere.end());
  return out;
}

// Every sphere whose influence ball holds the point is a candidate (the grid may return more).
TEST(BlockerGrid, CandidatesContainEverySphereThatCanReachThePoint) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> pos(-500, 500), rad(0.2f, 3.0f);
  std::vector<WorldSphere> spheres(400);
  for (auto& s : spheres) s = {{pos(rng), pos(rng), pos(rng) * 0.2f}, rad(rng)};
  spheres[17].radius = 0;  // blocks nothing, never a candidate
  const float min_sin = 0.05f;
  BlockerGrid g;
  g.build(spheres, min_sin);
  std::size_t returned = 0, needed = 0;
  for (int k = 0; k < 2000; ++k) {
    const glm::vec3 p{pos(rng), pos(rng), pos(rng) * 0.2f};
    const std::set<std::uint32_t> c = all_candidates(g, p);
    returned += c.size();
    EXPECT_EQ(c.count(17), 0u);
    for (std::uint32_t i = 0; i < spheres.size(); ++i) {
      if (!(spheres[i].radius > 0)) continue;
      if (glm::length(p - spheres[i].centre) <= influence_radius(spheres[i].radius, min_sin)) {
        ++needed;
        EXPECT_EQ(c.count(i), 1u) << "sphere " << i << " missing at point " << k;
      }
    }
  }
  // Not all pairs: the grid returns a small multiple of what is needed.
  EXPECT_LT(returned, 8 * needed + 2000);
  EXPECT_LT(returned, 2000u * spheres.size() / 4);
}

TEST(BlockerGrid, HugeSpheresAndNoCutOffGoEverywhere) {
  std::vector<WorldSphere> spheres = {{{0, 0, 0}, 1}, {{5, 0, 0}, 1}, {{0, 0, 0}, 500}};
  BlockerGrid g;
  g.build(spheres, 0.05f);
  EXPECT_EQ(all_candidates(g, {1e4f, 0, 0}), (std::set<std::uint32_t>{2}));
  g.build(spheres, 0.0f);  // no cut-off: every sphere reaches everywhere
  EXPECT_EQ(all_candidates(g, {1e4f, 0, 0}).size(), 3u);
}

TEST(BlockerGrid, EmptyAndZeroRadiusSetsHaveNoCandidates) {
  PENUMBRA_STABILITY("no blockers; blockers of radius 0", "no candidates", "-");
  BlockerGrid g;
  g.build({}, 0.05f);
  EXPECT_TRUE(all_candidates(g, {0, 0, 0}).empty());
  std::vector<WorldSphere> zero = {{{0, 0, 0}, 0}};
  g.build(zero, 0.05f);
  EXPECT_TRUE(all_candidates(g, {0, 0, 0}).empty());
}

}  // namespace
}  // namespace penumbra::blocker_accumulation
