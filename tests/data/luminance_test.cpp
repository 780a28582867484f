// data::luminance (penumbra/data/luminance.h): the Rec. 709 weights, linear in the colour.
#include "penumbra/data/luminance.h"

#include <gtest/gtest.h>

namespace penumbra::data {
namespace {

TEST(Luminance, Rec709Weights) {
  EXPECT_FLOAT_EQ(luminance({1.0f, 0.0f, 0.0f}), 0.2126f);
  EXPECT_FLOAT_EQ(luminance({0.0f, 1.0f, 0.0f}), 0.7152f);
  EXPECT_FLOAT_EQ(luminance({0.0f, 0.0f, 1.0f}), 0.0722f);
  EXPECT_FLOAT_EQ(luminance({1.0f, 1.0f, 1.0f}), 1.0f);  // white keeps its level
  EXPECT_FLOAT_EQ(luminance({2.0f, 4.0f, 8.0f}), 2 * 0.2126f + 4 * 0.7152f + 8 * 0.0722f);
  EXPECT_EQ(luminance({0.0f, 0.0f, 0.0f}), 0.0f);
}

}  // namespace
}  // namespace penumbra::data
