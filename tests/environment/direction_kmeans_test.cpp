// Deterministic weighted k-means on unit directions (direction_kmeans.h).
#include "penumbra/systems/environment/direction_kmeans.h"

#include <gtest/gtest.h>

#include <stdexcept>

#include "common/stability.h"
#include "synthetic_maps.h"

namespace env = penumbra::environment;
namespace t = penumbra::test;

namespace {

// Two tight groups of directions 90 degrees apart, 50 points each.
std::vector<glm::vec3> two_groups() {
  std::vector<glm::vec3> p;
  for (int i = 0; i < 50; ++i) p.push_back(t::dir_deg(10.0f + 0.1f * i, 20.0f));
  for (int i = 0; i < 50; ++i) p.push_back(t::dir_deg(100.0f, 20.0f + 0.1f * i));
  return p;
}

TEST(DirectionKMeans, SeparatesTwoGroups) {
  const auto p = two_groups();
  const std::vector<float> w(p.size(), 1.0f);
  const env::KMeansResult r = env::kmeans(p, w, 2, 0, 100);
  ASSERT_EQ(r.means.size(), 2u);
  for (int i = 0; i < 50; ++i) EXPECT_EQ(r.assignment[i], r.assignment[0]);
  for (int i = 50; i < 100; ++i) EXPECT_EQ(r.assignment[i], r.assignment[50]);
  EXPECT_NE(r.assignment[0], r.assignment[50]);
  const glm::vec3 m0 = r.means[static_cast<std::size_t>(r.assignment[0])];
  EXPECT_LT(t::angle_deg(m0, t::dir_deg(12.45f, 20.0f)), 0.05f);
  EXPECT_DOUBLE_EQ(r.weights[0] + r.weights[1], 100.0);
}

TEST(DirectionKMeans, DeterministicAndClampsK) {
  const auto p = two_groups();
  const std::vector<float> w(p.size(), 1.0f);
  const env::KMeansResult a = env::kmeans(p, w, 7, 3, 100), b = env::kmeans(p, w, 7, 3, 100);
  EXPECT_EQ(a.assignment, b.assignment);
  ASSERT_EQ(a.means.size(), b.means.size());
  for (std::size_t i = 0; i < a.means.size(); ++i) EXPECT_EQ(a.means[i], b.means[i]);
  // Three identical points: one cluster, whatever k.
  const std::vector<glm::vec3> same(3, glm::vec3(0, 0, 1));
  EXPECT_EQ(env::kmeans(same, {1, 1, 1}, 10, 0, 10).means.size(), 1u);
}

TEST(DirectionKMeans, BadInputThrows) {
  PENUMBRA_STABILITY("no directions; weights of another count; k 0 or larger than the points",
                     "std::invalid_argument", "-");
  const std::vector<glm::vec3> p(2, glm::vec3(1, 0, 0));
  EXPECT_THROW(env::kmeans({}, {}, 1, 0, 10), std::invalid_argument);
  EXPECT_THROW(env::kmeans(p, {1}, 1, 0, 10), std::invalid_argument);
  EXPECT_THROW(env::kmeans(p, {1, 1}, 1, 2, 10), std::invalid_argument);
  EXPECT_THROW(env::kmeans(p, {1, 1}, 0, 0, 10), std::invalid_argument);
}

}  // namespace
