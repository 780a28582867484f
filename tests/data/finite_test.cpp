// data::finite (penumbra/data/finite.h): every component of a vector or matrix is checked.
#include "penumbra/data/finite.h"

#include <gtest/gtest.h>

#include <limits>

namespace penumbra::data {
namespace {

constexpr float kNan = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

TEST(Finite, EachComponentOfAVectorCounts) {
  EXPECT_TRUE(finite(glm::vec2(1.0f, -2.0f)));
  EXPECT_TRUE(finite(glm::vec3(0.0f, std::numeric_limits<float>::max(), -1e-30f)));
  EXPECT_TRUE(finite(glm::vec4(1.0f)));
  for (int i = 0; i < 4; ++i) {
    for (float bad : {kNan, kInf, -kInf}) {
      glm::vec4 v(1.0f);
      v[i] = bad;
      EXPECT_FALSE(finite(v)) << "component " << i << " = " << bad;
      if (i < 3) {
        EXPECT_FALSE(finite(glm::vec3(v))) << "component " << i;
      }
      if (i < 2) {
        EXPECT_FALSE(finite(glm::vec2(v))) << "component " << i;
      }
    }
  }
  EXPECT_TRUE(finite(glm::dvec3(1.0, 2.0, 3.0)));
  EXPECT_FALSE(finite(glm::dvec3(1.0, std::numeric_limits<double>::quiet_NaN(), 3.0)));
}

TEST(Finite, EachEntryOfAMatrixCounts) {
  EXPECT_TRUE(finite(glm::mat4(1.0f)));
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      glm::mat4 m(1.0f);
      m[c][r] = kNan;
      EXPECT_FALSE(finite(m)) << "column " << c << ", row " << r;
      m[c][r] = -kInf;
      EXPECT_FALSE(finite(m)) << "column " << c << ", row " << r;
    }
  }
}

}  // namespace
}  // namespace penumbra::data
