// validate_horizon_input: every horizon method's bad-input errors name the field and the reason.
#include "penumbra/systems/terrain_shadow/horizon.h"
#include "terrain_test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include "common/stability.h"

namespace penumbra::terrain_shadow {
namespace {

std::string error_of(const data::HeightField& f, const HorizonParams& p, const TexelRect& r) {
  try {
    validate_horizon_input(f, p, r);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return {};
}

TEST(HorizonInput, AcceptsAValidField) {
  const auto f = test::flat_field(4, 3, 0.0f, 1.0f, "test.pgm");
  EXPECT_EQ(error_of(f, {}, TexelRect::all(f)), "");
  EXPECT_EQ(TexelRect::all(f).count(), 12u);
}

TEST(HorizonInput, RejectsNonFiniteHeightsNamingTheSample) {
  PENUMBRA_STABILITY("a NaN height", "std::invalid_argument naming the file and the sample (x, y)",
                     "-");
  auto f = test::flat_field(4, 4, 0.0f, 1.0f, "test.pgm");
  f.at(2, 3) = std::numeric_limits<float>::quiet_NaN();
  const std::string e = error_of(f, {}, TexelRect::all(f));
  EXPECT_NE(e.find("test.pgm"), std::string::npos) << e;
  EXPECT_NE(e.find("(2, 3)"), std::string::npos) << e;
  f.at(2, 3) = std::numeric_limits<float>::infinity();
  EXPECT_NE(error_of(f, {}, TexelRect::all(f)).find("not finite"), std::string::npos);
}

// The check runs in blocks of 1024 samples: a bad sample on a block's first or last place, or
// in the short last block, is found and named as well.
TEST(HorizonInput, RejectsNonFiniteHeightsInEveryBlock) {
  auto f = test::flat_field(40, 40, 0.0f, 1.0f, "test.pgm");  // 1600 samples: 1024 + 576
  for (const int i : {0, 1023, 1024, 1599}) {
    f.heights[static_cast<std::size_t>(i)] = std::numeric_limits<float>::quiet_NaN();
    const std::string e = error_of(f, {}, TexelRect::all(f));
    // Appended piece by piece: GCC 12 at -O3 warns falsely (-Wstringop-overflow) on
    // "literal" + std::string&&.
    std::string where = "(";
    where.append(std::to_string(i % 40)).append(", ").append(std::to_string(i / 40)).append(")");
    EXPECT_NE(e.find(where), std::string::npos) << i << ": " << e;
    f.heights[static_cast<std::size_t>(i)] = -std::numeric_limits<float>::infinity();
    EXPECT_NE(error_of(f, {}, TexelRect::all(f)).find(where), std::string::npos) << i;
    f.heights[static_cast<std::size_t>(i)] = 0.0f;
  }
  EXPECT_EQ(error_of(f, {}, TexelRect::all(f)), "");
}

TEST(HorizonInput, RejectsBadShapesAndParameters) {
  PENUMBRA_STABILITY(
      "bad cell size, azimuth count, height scale, rectangle outside, wrong height count",
      "std::invalid_argument naming the field", "-");
  EXPECT_NE(
      error_of(test::flat_field(1, 5, 0.0f, 1.0f, "test.pgm"), {}, {0, 0, 1, 5}).find("2 x 2"),
      std::string::npos);
  auto f = test::flat_field(4, 4, 0.0f, 1.0f, "test.pgm");
  f.cell_size = 0;
  EXPECT_NE(error_of(f, {}, TexelRect::all(f)).find("cell size"), std::string::npos);
  f.cell_size = 1;
  HorizonParams p;
  p.azimuths = 2;
  EXPECT_NE(error_of(f, p, TexelRect::all(f)).find("azimuths"), std::string::npos);
  p = {};
  p.height_scale = std::numeric_limits<float>::infinity();
  EXPECT_NE(error_of(f, p, TexelRect::all(f)).find("height scale"), std::string::npos);
  EXPECT_NE(error_of(f, {}, {0, 0, 5, 4}).find("outside"), std::string::npos);
  f.heights.pop_back();
  EXPECT_NE(error_of(f, {}, TexelRect::all(f)).find("heights for"), std::string::npos);
}

}  // namespace
}  // namespace penumbra::terrain_shadow
