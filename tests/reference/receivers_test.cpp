#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "penumbra/reference/estimators.h"
#include "reference_test_util.h"

namespace penumbra::reference {
namespace {

// A tilted plane h = 0.5 x - 0.25 y (in world units): positions on the samples, normals
// (-0.5, 0.25, 1) normalised everywhere, borders included (one-sided differences are exact).
TEST(HeightFieldReceivers, PositionsAndCentralDifferenceNormals) {
  data::HeightField f = test::flat_field(5, 4, 2.0f, 0);
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 5; ++x) f.at(x, y) = 0.5f * (2.0f * x) - 0.25f * (2.0f * y);
  }
  const auto rs = height_field_receivers({f, {10, 20, 30}});
  ASSERT_EQ(rs.size(), 20u);
  const glm::vec3 n = glm::normalize(glm::vec3(-0.5f, 0.25f, 1.0f));
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 5; ++x) {
      const Receiver& r = rs[y * 5 + x];
      EXPECT_EQ(r.position, glm::vec3(10 + 2.0f * x, 20 + 2.0f * y, 30 + f.at(x, y)));
      EXPECT_NEAR(glm::length(r.normal - n), 0, 1e-6f);
    }
  }
}

// A parabola h = x^2: central differences give the exact slope 2x inside.
TEST(HeightFieldReceivers, CentralDifferencesInside) {
  data::HeightField f = test::flat_field(6, 3, 1.0f, 0);
  for (int y = 0; y < 3; ++y) {
    for (int x = 0; x < 6; ++x) f.at(x, y) = static_cast<float>(x * x);
  }
  const auto rs = height_field_receivers({f, {0, 0, 0}});
  for (int x = 1; x < 5; ++x) {
    const glm::vec3 n = glm::normalize(glm::vec3(-2.0f * x, 0, 1));
    EXPECT_NEAR(glm::length(rs[6 + x].normal - n), 0, 1e-6f) << x;
  }
  // Border: one-sided slope (1 - 0) / 1 at x = 0.
  EXPECT_NEAR(glm::length(rs[0].normal - glm::normalize(glm::vec3(-1, 0, 1))), 0, 1e-6f);
  EXPECT_THROW(height_field_receivers({test::flat_field(1, 3, 1, 0), {0, 0, 0}}),
               std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::reference
