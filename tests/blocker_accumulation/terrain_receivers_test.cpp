#include "penumbra/systems/blocker_accumulation/terrain_receivers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "test_skies.h"

namespace penumbra::blocker_accumulation {
namespace {

// A flat 65 x 65 field (1 m cells, centred on the origin): horizons 0, normals up, lighting 1.
struct Flat {
  data::HeightField field;
  terrain_shadow::HorizonGrid horizons;
  std::vector<glm::vec3> normals, base;
  TerrainReceivers t;
  Flat() {
    field.width = field.height = 65;
    field.cell_size = 1;
    field.heights.assign(65 * 65, 0.0f);
    field.source = "flat";
    horizons.resize(65, 65, 32);
    normals.assign(65 * 65, glm::vec3(0, 0, 1));
    base.assign(65 * 65, glm::vec3(1.0f));
    t = {&field, {-32, -32, 0}, 1.0f, &horizons, &normals};
  }
  float at(const std::vector<glm::vec3>& v, int x, int y) const {
    return v[(y + 32) * 65 + x + 32].x;
  }
};

sh::CoeffsRgb<N> uniform_sky() {
  sh::CoeffsRgb<N> r{};
  for (auto& c : r) c[0] = std::sqrt(4 * std::numbers::pi_v<float>);
  return r;
}

TEST(TerrainReceivers, ShadowUnderTheBlockerAndNothingBeyondItsReach) {
  Flat f;
  BlockerAccumulation<N> acc;
  acc.set_blockers({{{0, 0, 3}, 2}});
  const terrain_shadow::LogWedge<N> wedges(32, std::log(0.2f));
  TerrainShadeStats stats;
  const std::vector<glm::vec3> out =
      shade_terrain_receivers<N>(f.t, acc, wedges, uniform_sky(), f.base, &stats);
  // Exact for an opaque sphere seen from below: 1 - sin^2(asin(2/3)) = 0.56; eps 0.2 lets 20%
  // through (0.64), the SH path lands near it.
  std::printf("under the blocker: %.3f (exact opaque 0.556), reached %zu, changed %zu\n",
              f.at(out, 0, 0), stats.reached, stats.changed);
  EXPECT_NEAR(f.at(out, 0, 0), 0.6f, 0.08f);
  EXPECT_GT(stats.reached, 1000u);  // reach 2 (1/0.02 + 1) = 102 m: the whole field
  // Away from the blocker the shadow fades smoothly: beyond 10 m no step between neighbours
  // above 0.5% (near it the true penumbra is steep: ~10% per metre under the sphere's edge).
  float worst = 0;
  for (int y = -32; y <= 32; ++y)
    for (int x = -32; x < 32; ++x)
      if (x * x + y * y > 100)
        worst = std::max(worst, std::abs(f.at(out, x + 1, y) - f.at(out, x, y)));
  std::printf("largest step beyond 10 m: %.4f\n", worst);
  EXPECT_LT(worst, 0.005f);
  EXPECT_GT(f.at(out, 30, 30), 0.99f);

  // A small blocker reaches only the texels near it; the rest are the base, bit for bit.
  acc.set_blockers({{{0, 0, 1}, 0.05f}});
  const std::vector<glm::vec3> small =
      shade_terrain_receivers<N>(f.t, acc, wedges, uniform_sky(), f.base, &stats);
  EXPECT_LT(stats.reached, 40u);
  EXPECT_EQ(f.at(small, 10, 0), 1.0f);
}

// Every second texel shaded, the others interpolated: against every texel, the shadow of a 2 m
// sphere (4 texels wide, 1 m above the ground) differs only along its penumbra; the lattice's
// own texels are the same bit for bit.
TEST(TerrainReceivers, EverySecondTexelAgainstEveryTexel) {
  Flat f;
  BlockerAccumulation<N> acc;
  acc.set_blockers({{{0.3f, -0.4f, 3}, 2}});
  const terrain_shadow::LogWedge<N> wedges(32, std::log(0.2f));
  std::vector<glm::vec3> full, half;
  update_terrain_ratios<N>(f.t, acc, wedges, uniform_sky(), full, 0, 1, 1);
  update_terrain_ratios<N>(f.t, acc, wedges, uniform_sky(), half, 0, 1, 2);
  float worst = 0, sq = 0;
  for (std::size_t i = 0; i < full.size(); ++i) {
    const int x = static_cast<int>(i % 65), y = static_cast<int>(i / 65);
    if (x % 2 == 0 && y % 2 == 0) {
      EXPECT_EQ(half[i], full[i]) << x << ", " << y;
    }
    worst = std::max(worst, std::abs(half[i].x - full[i].x));
    sq += (half[i].x - full[i].x) * (half[i].x - full[i].x);
  }
  std::printf("every second texel: largest ratio difference %.4f, RMS %.5f\n", worst,
              std::sqrt(sq / full.size()));
  // Measured: 7.2% at the steepest of the penumbra (about 10% per texel there), 0.2% RMS.
  EXPECT_LT(worst, 0.1f);
  EXPECT_LT(std::sqrt(sq / full.size()), 0.005f);
  // Spread over 3 frames (period 3) the lattice rows of each phase are recomputed once.
  std::vector<glm::vec3> spread;
  for (int phase = 0; phase < 3; ++phase)
    update_terrain_ratios<N>(f.t, acc, wedges, uniform_sky(), spread, phase, 3, 2);
  EXPECT_EQ(spread, half);
}

TEST(TerrainReceivers, NoBlockersLeaveTheBaseAndMismatchedInputIsNamed) {
  Flat f;
  BlockerAccumulation<N> acc;
  const terrain_shadow::LogWedge<N> wedges(32, std::log(0.2f));
  TerrainShadeStats stats;
  EXPECT_EQ(shade_terrain_receivers<N>(f.t, acc, wedges, uniform_sky(), f.base, &stats), f.base);
  EXPECT_EQ(stats.reached, 0u);
  std::vector<glm::vec3> short_base(10, glm::vec3(1.0f));
  try {
    shade_terrain_receivers<N>(f.t, acc, wedges, uniform_sky(), short_base);
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("flat"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace penumbra::blocker_accumulation
