// TerrainShadowing: edits recompute exactly what a full update would, lights and environment
// shade from stored transfer, and the documented degenerate cases give finite results.
#include "penumbra/systems/terrain_shadow/terrain_shadowing.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

#include "penumbra/assets/procedural.h"
#include "penumbra/systems/terrain_shadow/terrain_edit.h"

#include "common/stability.h"
#include "terrain_test_util.h"

namespace penumbra::terrain_shadow {
namespace {

using test::mountains;

sh::CoeffsRgb<4> constant_sky(float radiance) {
  sh::CoeffsRgb<4> l{};
  for (auto& c : l) c[0] = radiance * std::sqrt(4 * kPi);  // y_00 = 1 / sqrt(4 pi)
  return l;
}

// Two 16-azimuth systems on a 48^2 field: `edited` takes edits, `fresh` full updates of the
// same fields, to compare with.
struct EditAgainstFullUpdate : ::testing::Test {
  static TerrainShadowConfig sixteen_azimuths() {
    TerrainShadowConfig config;
    config.azimuths = 16;
    return config;
  }
  TerrainShadowing<4> edited{sixteen_azimuths()}, fresh{sixteen_azimuths()};
  std::shared_ptr<const data::HeightField> field = mountains(48);
  void SetUp() override { edited.update(field, 1.0f); }
};

TEST_F(EditAgainstFullUpdate, EditUpdateEqualsAFullUpdate) {
  for (BrushKind kind : {BrushKind::kCrater, BrushKind::kRaise, BrushKind::kSmooth}) {
    Brush b;
    b.kind = kind;
    b.centre = {40.0f, 50.0f};
    b.radius = 9.0f;
    b.strength = kind == BrushKind::kSmooth ? 1.0f : 12.0f;
    const EditResult e = apply_brush(field, b);
    ASSERT_FALSE(e.changed.empty());
    const UpdateStats s = edited.update_edit(e.field, 1.0f, e.changed);
    fresh.update(e.field, 1.0f);
    field = e.field;
    EXPECT_FALSE(s.full);
    EXPECT_LT(s.horizon_pairs, 48u * 48u * 16u) << "an edit recomputes only what it can change";
    EXPECT_GT(s.transfer_texels, 0u);
    for (std::size_t i = 0; i < fresh.horizons().angles.size(); ++i)
      ASSERT_NEAR(edited.horizons().angles[i], fresh.horizons().angles[i], 2e-6f) << i;
    for (std::size_t i = 0; i < fresh.transfer().size(); ++i)
      for (int c = 0; c < 16; ++c)
        ASSERT_NEAR(edited.transfer()[i][c], fresh.transfer()[i][c], 1e-4f) << i << " " << c;
    // An edit's changed texels get their transfer in batches of eight wherever they lie (a list
    // in blocks, not rows); the couplings give the same bits in a batch as alone, so the edit's
    // transfer is a full update's, bit for bit.
    ASSERT_EQ(edited.transfer().size(), fresh.transfer().size());
    EXPECT_EQ(std::memcmp(edited.transfer().data(), fresh.transfer().data(),
                          fresh.transfer().size() * sizeof(fresh.transfer()[0])),
              0);
  }
}

// An edit whose field has a non-finite height throws, naming the sample, and leaves the shading
// as it was: the next good edit still equals a full update, bit for bit.
TEST_F(EditAgainstFullUpdate, ANonFiniteEditThrowsAndChangesNothing) {
  const auto horizons = edited.horizons().angles;
  const auto transfer = edited.transfer();
  Brush b;
  b.centre = {40.0f, 50.0f};
  b.radius = 9.0f;
  b.strength = 12.0f;
  EditResult bad = apply_brush(field, b);
  auto nan_field = std::make_shared<data::HeightField>(*bad.field);
  nan_field->heights[static_cast<std::size_t>(20) * 48 + 19] =
      std::numeric_limits<float>::quiet_NaN();
  try {
    edited.update_edit(nan_field, 1.0f, bad.changed);
    ADD_FAILURE() << "a NaN height was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("(19, 20)"), std::string::npos) << e.what();
  }
  EXPECT_EQ(&edited.field(), field.get());
  EXPECT_EQ(edited.horizons().angles, horizons);
  EXPECT_EQ(
      std::memcmp(edited.transfer().data(), transfer.data(), transfer.size() * sizeof(transfer[0])),
      0);
  const EditResult good = apply_brush(field, b);
  edited.update_edit(good.field, 1.0f, good.changed);
  fresh.update(good.field, 1.0f);
  EXPECT_EQ(edited.horizons().angles, fresh.horizons().angles);
  EXPECT_EQ(std::memcmp(edited.transfer().data(), fresh.transfer().data(),
                        fresh.transfer().size() * sizeof(fresh.transfer()[0])),
            0);
}

TEST(TerrainShadowing, FlatGroundSeesTheWholeSky) {
  TerrainShadowing<4> ts;
  ts.update(test::shared_flat(16), 1.0f);
  std::vector<glm::vec3> e;
  ts.shade_environment(constant_sky(2.0f), e);
  // E = pi L for an unoccluded upward receiver; 4 bands of the hemisphere x cosine product
  // keep the DC term within 2%.
  for (const glm::vec3& v : e) EXPECT_NEAR(v.x, kPi * 2.0f, 0.02f * kPi * 2.0f);
}

TEST(TerrainShadowing, ValleyIsDarkerThanRidgeAndEverythingIsFinite) {
  TerrainShadowing<4> ts;
  auto f =
      std::make_shared<data::HeightField>(assets::procedural_scene("sine_grating", {64, 64.0f}, 1));
  ts.update(f, 4.0f);  // steepened: ridges 4x the default amplitude
  std::vector<glm::vec3> e;
  ts.shade_environment(constant_sky(1.0f), e);
  float lo = 1e9f, hi = -1e9f;
  for (const glm::vec3& v : e) {
    ASSERT_TRUE(std::isfinite(v.x));
    lo = std::min(lo, v.x);
    hi = std::max(hi, v.x);
  }
  EXPECT_LT(lo, 0.8f * hi);  // grooves see less sky than crests
  EXPECT_LE(hi, kPi * 1.03f);
}

TEST(TerrainShadowing, LightFacingAFlatReceiverMatchesTheClosedForm) {
  TerrainShadowing<4> ts;
  ts.update(test::shared_flat(32), 1.0f);
  std::vector<glm::vec3> e;
  const float r = 1.0f, d = 10.0f;
  ts.add_spherical_light({16.0f, 16.0f, d}, r, glm::vec3(3.0f), e);
  // Straight above: E = pi L sin^2(theta) with sin(theta) = r / d. Measured +6.2%: the
  // clamped cosine cut to 4 bands overshoots near the normal (its band-3 term is 0).
  const float expected = kPi * 3.0f * (r / d) * (r / d);
  EXPECT_NEAR(e[16 * 32 + 16].x, expected, 0.08f * expected);
  // Farther receivers get less.
  EXPECT_LT(e[16 * 32 + 2].x, e[16 * 32 + 16].x);
}

// A key light (add_key_light): on flat ground E = irradiance x cos; behind a wall, the share of
// the disc above the wall's horizon (half when the wall's top is at the disc's centre, none
// when above its rim); bad input rejected.
TEST(TerrainShadowing, KeyLightIsTheCosineTimesTheDiscAboveTheHorizon) {
  TerrainShadowing<4> flat;
  flat.update(test::shared_flat(32), 1.0f);
  const glm::vec3 d = glm::normalize(glm::vec3(1.0f, 0.5f, 1.0f));
  std::vector<float> h;
  flat.key_light_horizons(d, h);
  std::vector<glm::vec3> e;
  flat.add_key_light(d, 0.01f, glm::vec3(2.0f, 1.0f, 0.5f), h, e);
  EXPECT_NEAR(e[16 * 32 + 16].x, 2.0f * d.z, 1e-5f);
  EXPECT_NEAR(e[16 * 32 + 16].z, 0.5f * d.z, 1e-5f);

  auto wall = std::make_shared<data::HeightField>(*test::shared_flat(64));
  for (int y = 0; y < 64; ++y) wall->at(40, y) = 10;  // 10 m high at x = 40 (1 m cells)
  TerrainShadowing<4> ts;
  ts.update(wall, 1.0f);
  // A sun towards +x at the elevation of the wall's top seen from x = 30: atan(10 / 10) = 45
  // degrees. The texel there sees half the disc; nearer the wall none, farther away all.
  const float a = 0.05f;
  const glm::vec3 sun(std::cos(kPi / 4), 0.0f, std::sin(kPi / 4));
  ts.key_light_horizons(sun, h);
  e.assign(64 * 64, glm::vec3(0.0f));
  ts.add_key_light(sun, a, glm::vec3(1.0f), h, e);
  const float open = sun.z;  // flat texel, the whole disc: cos = sun.z
  EXPECT_NEAR(e[32 * 64 + 30].x, 0.5f * open, 0.05f * open);
  EXPECT_EQ(e[32 * 64 + 35].x, 0.0f);
  EXPECT_NEAR(e[32 * 64 + 10].x, open, 1e-5f);
  EXPECT_GT(e[32 * 64 + 29].x, e[32 * 64 + 30].x);  // a little farther: more of the disc

  EXPECT_THROW(ts.add_key_light(glm::vec3(0, 0, 2), a, glm::vec3(1.0f), h, e),
               std::invalid_argument);
  EXPECT_THROW(ts.add_key_light(sun, -1.0f, glm::vec3(1.0f), h, e), std::invalid_argument);
  EXPECT_THROW(ts.add_key_light(sun, a, glm::vec3(NAN), h, e), std::invalid_argument);
  const std::vector<float> short_h(10);
  EXPECT_THROW(ts.add_key_light(sun, a, glm::vec3(1.0f), short_h, e), std::invalid_argument);
  TerrainShadowing<4> empty;
  EXPECT_THROW(empty.key_light_horizons(sun, h), std::invalid_argument);
}

// Radius 0, a receiver inside the light and a light under the terrain are covered for both
// shading modes in light_shading_test.cpp; here, what add_spherical_light rejects.
TEST(TerrainShadowing, RejectsInvalidLights) {
  PENUMBRA_STABILITY("a light of negative radius or non-finite radiance", "std::invalid_argument",
                     "-");
  TerrainShadowing<4> ts;
  ts.update(mountains(32), 1.0f);
  std::vector<glm::vec3> e;
  EXPECT_THROW(ts.add_spherical_light({0, 0, 1}, -1.0f, glm::vec3(1.0f), e), std::invalid_argument);
  EXPECT_THROW(
      ts.add_spherical_light({0, 0, std::numeric_limits<float>::quiet_NaN()}, 1, glm::vec3(1), e),
      std::invalid_argument);
}

TEST(TerrainShadowing, RejectsBadInputNamingIt) {
  PENUMBRA_STABILITY("a NaN height in a loaded map; bad config",
                     "std::invalid_argument naming the map", "-");
  auto f = std::make_shared<data::HeightField>(*test::shared_flat(8));
  f->at(3, 4) = std::numeric_limits<float>::quiet_NaN();
  f->source = "broken.pgm";
  TerrainShadowing<4> ts;
  try {
    ts.update(f, 1.0f);
    FAIL() << "NaN height accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("broken.pgm"), std::string::npos) << e.what();
  }
  TerrainShadowConfig bad;
  bad.azimuths = 2;
  EXPECT_THROW(TerrainShadowing<4>{bad}, std::invalid_argument);
}

TEST(TerrainShadowing, SpikesAndExtremeSlopesStayFinite) {
  auto f = std::make_shared<data::HeightField>(*test::shared_flat(24));
  f->at(12, 12) = 1e5f;  // a single-texel spike, near-vertical slopes
  TerrainShadowing<4> ts;
  ts.update(f, 1.0f);
  std::vector<glm::vec3> e;
  ts.shade_environment(constant_sky(1.0f), e);
  ts.add_spherical_light({5, 5, 10}, 1, glm::vec3(1.0f), e);
  for (const glm::vec3& v : e) ASSERT_TRUE(std::isfinite(v.x) && std::isfinite(v.z));
  EXPECT_LT(e[12 * 24 + 11].x, e[2 * 24 + 2].x);  // beside the spike: much of the sky is gone
}

}  // namespace
}  // namespace penumbra::terrain_shadow
