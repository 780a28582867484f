#include "penumbra/systems/blocker_accumulation/blocker_log_sum.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include <glm/geometric.hpp>
#include "common/stability.h"

namespace penumbra::blocker_accumulation {
namespace {

struct Blocker {
  glm::vec3 centre;
  float radius, scale;
};

// Spheres around a receiver at the origin: far and near, above, crossing and below the tangent
// plane, one containing the receiver, one centred on it, zero radius, tiny (under min_sin).
std::vector<Blocker> mixed_blockers(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1, 1);
  std::vector<Blocker> out;
  for (int i = 0; i < count; ++i) {
    const float cz = 2 * u(rng) + 0.5f, cy = 3 * u(rng),
                cx = 3 * u(rng);  // GCC's order (random_draws.h)
    const glm::vec3 c(cx, cy, cz);
    const float r = 0.05f + 0.8f * (0.5f + 0.5f * u(rng));
    out.push_back({c, r, i % 5 == 0 ? 0.3f : 1.0f});
  }
  out.push_back({glm::vec3(0.1f, 0, 0.1f), 0.5f, 1});  // contains the receiver
  out.push_back({glm::vec3(0), 0.4f, 1});              // centred on it
  out.push_back({glm::vec3(0, 0, 1), 0, 1});           // zero radius
  out.push_back({glm::vec3(0, 0, 50), 0.1f, 1});       // below min_sin
  out.push_back({glm::vec3(0, 0, -2), 1, 1});          // below the tangent plane
  return out;
}

// The per-blocker path: view_blocker + add_log_visibility, as BlockerAccumulation did.
template <int N>
void expect_matches_per_blocker(const SphereBlockerSettings& s, int count) {
  const glm::vec3 p(0), n = glm::normalize(glm::vec3(0.2f, -0.1f, 1));
  const float log_eps = std::log(s.epsilon);
  const std::vector<Blocker> blockers = mixed_blockers(count, 7 + count);
  sh::Coeffs<N> expected{}, got{};
  std::size_t adds = 0;
  float weight = 0;
  std::vector<glm::vec3> axes;
  BlockerLogSum<N> lanes(p, n, s, log_eps);
  for (const Blocker& b : blockers) {
    BlockerView v = view_blocker(p, n, b.centre, b.radius, s);
    v.weight *= b.scale;
    if (v.weight > 0) {
      add_log_visibility<N>(v, log_eps, expected);
      ++adds;
      weight += v.weight;
      axes.push_back(v.axis);
    }
    lanes.add(b.centre, b.radius, b.scale);
  }
  lanes.finish(got);
  EXPECT_EQ(lanes.views(), blockers.size());
  EXPECT_EQ(lanes.adds(), adds);
  EXPECT_NEAR(lanes.weight(), weight, 1e-4f * (1 + weight));
  float scale = 0;
  for (float x : expected) scale = std::max(scale, std::abs(x));
  for (int i = 0; i < N * N; ++i) EXPECT_NEAR(got[i], expected[i], 2e-5f * (1 + scale)) << i;
  // The depth limit's view: the sum's lowest value at the contributing blockers' axes.
  ASSERT_LE(blockers.size(), std::size_t{8 * BlockerLogSum<N>::kMaxSteps});
  float lowest = 0;
  for (const glm::vec3& a : axes) lowest = std::min(lowest, sh::evaluate<N>(got, a));
  EXPECT_NEAR(lanes.lowest_at_axes(got), lowest, 1e-4f * (1 + scale));
}

TEST(BlockerLogSum, MatchesPerBlockerViewsAndCaps) {
  for (int count : {0, 3, 8, 13, 100}) {
    SCOPED_TRACE(count);
    expect_matches_per_blocker<3>({}, count);
    expect_matches_per_blocker<4>({}, count);
    expect_matches_per_blocker<5>({}, count);
  }
}

TEST(BlockerLogSum, MatchesWithRatioAttenuationAndNoSizeCut) {
  SphereBlockerSettings s;
  s.ratio = RatioAttenuation::kOn;
  s.min_sin = 0;
  s.epsilon = 0.05f;
  expect_matches_per_blocker<4>(s, 40);
}

TEST(BlockerLogSum, NothingAddedGivesZeroSumAndNoAxes) {
  PENUMBRA_STABILITY("blockers below the plane or of scale 0 only",
                     "counted as views, nothing added: zero log sum", "-");
  BlockerLogSum<4> lanes(glm::vec3(0), glm::vec3(0, 0, 1), {}, std::log(0.2f));
  lanes.add(glm::vec3(0, 0, -5), 1, 1);  // below the plane
  lanes.add(glm::vec3(0, 0, 5), 1, 0);   // scale 0
  sh::Coeffs<4> sum{};
  lanes.finish(sum);
  EXPECT_EQ(lanes.views(), 2u);
  EXPECT_EQ(lanes.adds(), 0u);
  EXPECT_EQ(lanes.axis_steps(), 0);
  EXPECT_EQ(lanes.lowest_at_axes(sum), 0.0f);
  for (float x : sum) EXPECT_EQ(x, 0.0f);
}

// The cluster centre's view: each sphere as view_blocker sees it with the normal towards it.
TEST(BlockerLogSum, TowardsCentreMatchesNormalPointingAtEachSphere) {
  const SphereBlockerSettings s;
  const float log_eps = std::log(s.epsilon);
  const glm::vec3 p(0.3f, -0.2f, 0.1f);
  sh::Coeffs<4> expected{}, got{};
  BlockerLogSum<4> lanes(p, s, log_eps);
  std::size_t adds = 0;
  for (const Blocker& b : mixed_blockers(30, 11)) {
    const glm::vec3 to = b.centre - p;
    const float d = glm::length(to);
    const glm::vec3 n = d > 0 ? to / d : glm::vec3(0, 0, 1);
    BlockerView v = view_blocker(p, n, b.centre, b.radius, s);
    v.weight *= b.scale;
    if (v.weight > 0) {
      add_log_visibility<4>(v, log_eps, expected);
      ++adds;
    }
    lanes.add(b.centre, b.radius, b.scale);
  }
  lanes.finish(got);
  EXPECT_EQ(lanes.adds(), adds);
  for (int i = 0; i < 16; ++i) EXPECT_NEAR(got[i], expected[i], 1e-4f) << i;
}

}  // namespace
}  // namespace penumbra::blocker_accumulation
