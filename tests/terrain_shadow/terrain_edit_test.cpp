// Brushes: what they change, where, and what they reject.
#include "penumbra/systems/terrain_shadow/terrain_edit.h"
#include "terrain_test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include "common/stability.h"

namespace penumbra::terrain_shadow {
namespace {

TEST(TerrainEdit, CraterLowersOnlyInsideItsRect) {
  const auto f = test::shared_flat(32, 5.0f, 2.0f);
  Brush b{BrushKind::kCrater, {20.0f, 30.0f}, 6.0f, 3.0f};
  const EditResult e = apply_brush(f, b);
  EXPECT_NEAR(e.field->at(10, 15), 5.0f - 3.0f, 1e-6f);  // centre: full depth
  EXPECT_EQ(f->at(10, 15), 5.0f);                        // the input is untouched
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x)
      if (!e.changed.contains(x, y)) {
        ASSERT_EQ(e.field->at(x, y), 5.0f) << x << "," << y;
      }
  EXPECT_LE(e.changed.width(), 7);  // 2 * radius / cell + 1
}

TEST(TerrainEdit, RaiseAndSmooth) {
  const auto f = test::shared_flat(16, 5.0f, 2.0f);
  const EditResult up = apply_brush(f, {BrushKind::kRaise, {16, 16}, 5.0f, 2.0f});
  EXPECT_NEAR(up.field->at(8, 8), 7.0f, 1e-6f);
  const EditResult smooth = apply_brush(up.field, {BrushKind::kSmooth, {16, 16}, 5.0f, 1.0f});
  EXPECT_LT(smooth.field->at(8, 8), 7.0f);  // the peak comes down towards its neighbours
  EXPECT_GT(smooth.field->at(8, 8), 5.0f);
}

TEST(TerrainEdit, OffFieldChangesNothingAndBadBrushesThrow) {
  PENUMBRA_STABILITY("a brush off the field; radius 0, bad smoothing strength, NaN centre",
                     "nothing changed; bad brushes std::invalid_argument", "-");
  const auto f = test::shared_flat(8, 5.0f, 2.0f);
  const EditResult e = apply_brush(f, {BrushKind::kCrater, {500, 500}, 3, 1});
  EXPECT_TRUE(e.changed.empty());
  EXPECT_EQ(e.field, f);
  EXPECT_THROW(apply_brush(f, {BrushKind::kCrater, {1, 1}, 0.0f, 1}), std::invalid_argument);
  EXPECT_THROW(apply_brush(f, {BrushKind::kSmooth, {1, 1}, 2, 1.5f}), std::invalid_argument);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(apply_brush(f, {BrushKind::kRaise, {nan, 1}, 2, 1}), std::invalid_argument);
}

TEST(TerrainEdit, TerrainComponentGetsNewHeightsVersionAndRect) {
  components::Terrain t;
  t.heights = test::shared_flat(16, 5.0f, 2.0f);
  t.origin = {-16.0f, -16.0f, 100.0f};
  t.height_scale = 2.0f;
  const auto before = t.heights;
  // World centre (0, 0) is sample (8, 8); a 4 m world crater is 2 m of stored height.
  ASSERT_TRUE(apply_brush(t, {BrushKind::kCrater, {0.0f, 0.0f}, 3.0f, 4.0f}));
  EXPECT_NE(t.heights, before);
  EXPECT_EQ(t.version, 1u);
  EXPECT_NEAR(t.heights->at(8, 8), 3.0f, 1e-6f);
  EXPECT_TRUE(t.edited.x0 <= 8 && t.edited.x1 > 8 && t.edited.y0 <= 8 && t.edited.y1 > 8);
  EXPECT_FALSE(apply_brush(t, {BrushKind::kCrater, {900.0f, 0.0f}, 3.0f, 4.0f}));
  EXPECT_EQ(t.version, 1u);
}

}  // namespace
}  // namespace penumbra::terrain_shadow
